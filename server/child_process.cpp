#include "child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <memory>
#include <string_view>
#include <thread>

namespace cgview::server {

namespace {

constexpr int kServerFd = 3;

// The read end of the server's life pipe: made once; its write end is never
// closed, so it closes when the server's process ends, however it ends.
int server_life_fd() {
  static const int fd = [] {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return -1;
    return fds[0];
  }();
  return fd;
}

const std::vector<std::string>& passed_names() {
  // A trailing '_' names a prefix.
  static const std::vector<std::string> names = {"PATH",
                                                 "LANG",
                                                 "LC_ALL",
                                                 "LC_CTYPE",
                                                 "TZ",
                                                 "LD_LIBRARY_PATH",
                                                 "CGVIEW_GL_PLATFORM",
                                                 "CGVIEW_PLUGIN_",
                                                 "__EGL_",
                                                 "__GLX_",
                                                 "EGL_",
                                                 "MESA_",
                                                 "LIBGL_",
                                                 "GALLIUM_",
                                                 "LP_",
                                                 "OMP_",
                                                 "TBB_",
                                                 "CUDA_",
                                                 "NVIDIA_",
                                                 "CCACHE_"};
  return names;
}

}  // namespace

void end_with_server() {
  const char* v = std::getenv("CGVIEW_SERVER_FD");
  if (!v) return;
  const int fd = std::atoi(v);
  ::unsetenv("CGVIEW_SERVER_FD");
  ::fcntl(fd, F_SETFD, FD_CLOEXEC);  // not the compiler's, nor a plugin's children's
  std::thread([fd] {
    char c;
    ssize_t n;
    do n = ::read(fd, &c, 1);
    while (n < 0 && errno == EINTR);
    if (n > 0) return;  // the server never writes to it
    ::kill(0, SIGKILL);
    ::_exit(137);
  }).detach();
}

std::vector<std::string> job_environment() {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) {
    const std::string_view var(*e);
    const std::string_view name = var.substr(0, var.find('='));
    for (const std::string& n : passed_names())
      if (n.back() == '_' ? name.starts_with(n) : name == n) {
        env.emplace_back(var);
        break;
      }
  }
  return env;
}

namespace {

// What the child needs, made before it starts: it shares the server's
// memory until its exec and must not allocate.
struct ChildStart {
  const ChildOptions* options;
  char** argv;
  char** envp;
  const char* err;
  rlim_t limit;
  int life;
  sigset_t mask;  // the server's thread's, restored once the handlers are the default
};

// The child, from its start to its exec: only system calls.
int child_main(void* p) {
  const ChildStart& s = *static_cast<const ChildStart*>(p);
  const ChildOptions& options = *s.options;
  // Its signals' handlers are still the server's (Asio's among them, which
  // would write to the server's signal pipe): the default for each before
  // any is unblocked.
  for (int sig = 1; sig < NSIG; ++sig) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler != SIG_DFL && old.sa_handler != SIG_IGN)
      ::signal(sig, SIG_DFL);
  }
  ::pthread_sigmask(SIG_SETMASK, &s.mask, nullptr);
  if (s.life < 0) ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // a killed server leaves no child behind
  ::setpgid(0, 0);
  if (s.limit > 0) {
    struct rlimit rl {
      s.limit, s.limit
    };
    ::setrlimit(RLIMIT_AS, &rl);
  }
  struct rlimit core {
    0, 0
  };
  ::setrlimit(RLIMIT_CORE, &core);
  if (options.file_mb > 0) {
    const rlim_t f = rlim_t(options.file_mb) << 20;
    struct rlimit rl {
      f, f
    };
    ::setrlimit(RLIMIT_FSIZE, &rl);
  }
  if (options.processes > 0) {
    struct rlimit rl {
      rlim_t(options.processes), rlim_t(options.processes)
    };
    ::setrlimit(RLIMIT_NPROC, &rl);
  }
  // Out of the way of the numbers given below first (a parent's data_fd may be 3).
  const int data = options.data_fd >= 0 ? ::fcntl(options.data_fd, F_DUPFD_CLOEXEC, kChildDataFd + 1) : -1;
  const int null = ::open("/dev/null", O_RDWR);
  if (options.stdin_fd >= 0) ::dup2(options.stdin_fd, 0);
  else if (null >= 0) ::dup2(null, 0);
  if (options.stdout_fd >= 0) ::dup2(options.stdout_fd, 1);
  else if (null >= 0) ::dup2(null, 1);
  const int e = options.stderr_to_stdout || options.stderr_fd >= 0 || *s.err == '\0'
                    ? -1
                    : ::open(s.err, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (options.stderr_to_stdout) ::dup2(1, 2);
  else if (options.stderr_fd >= 0) ::dup2(options.stderr_fd, 2);
  else if (e >= 0) ::dup2(e, 2);
  else if (null >= 0) ::dup2(null, 2);
  // After the files above, opened in the server's namespace, and before its
  // descriptor may be taken by the life pipe's.  (Failing, the child starts
  // in the server's namespace, which holds the same files.)
  if (options.mount_ns_fd >= 0) ::setns(options.mount_ns_fd, CLONE_NEWNS);
  // Last, as the stdio descriptors above may have taken 3 meanwhile.
  if (s.life == kServerFd) ::fcntl(kServerFd, F_SETFD, 0);
  else if (s.life >= 0) ::dup2(s.life, kServerFd);
  if (data >= 0) {
    ::dup2(data, kChildDataFd);
    if (s.life < 0) ::close(kServerFd);
  }
  // Nothing else of the server's: its listening socket, clients' sockets and
  // the store's files are not the child's to hold open or write.
  ::close_range(data >= 0 ? kChildDataFd + 1 : s.life >= 0 ? kServerFd + 1 : kServerFd, ~0U, 0);
  ::execve(s.argv[0], s.argv, s.envp);
  ::_exit(127);
}

}  // namespace

pid_t spawn_child(const std::vector<std::string>& args, const ChildOptions& options) {
  std::vector<std::string> copy = args;
  std::vector<char*> argv;
  for (auto& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  // The environment is made before the child starts (nothing that allocates after it).
  const int life = options.end_with_server ? server_life_fd() : -1;
  std::string life_var = "CGVIEW_SERVER_FD=" + std::to_string(kServerFd);
  std::vector<char*> envp;
  std::vector<std::string> clean;
  if (options.clean_env) {
    clean = job_environment();
    clean.push_back("HOME=/tmp");
    clean.push_back("TMPDIR=/tmp");
    for (std::string& e : clean) envp.push_back(e.data());
  } else {
    for (char** e = environ; *e; ++e)
      if (!std::string_view(*e).starts_with("CGVIEW_SERVER_FD=")) envp.push_back(*e);
  }
  if (life >= 0) envp.push_back(life_var.data());
  envp.push_back(nullptr);
  const std::string err = options.stderr_file.string();
  ChildStart start{&options, argv.data(), envp.data(), err.c_str(), rlim_t(options.memory_mb) << 20, life, {}};
  // The child shares the server's memory until its exec, the server's
  // thread waiting meanwhile (CLONE_VM | CLONE_VFORK, as posix_spawn does):
  // a fork copied the server's page tables for each job and then paid a
  // page fault for each page either side wrote, ~1 ms of the server's CPU
  // a job in a burst.  Every signal is blocked until the child has reset
  // its handlers: a SIGTERM in between (a job cancelled at once) would run
  // the server's handler, Asio's, in the child.
  sigset_t all;
  sigfillset(&all);
  ::pthread_sigmask(SIG_BLOCK, &all, &start.mask);
  constexpr std::size_t kStack = 64 << 10;
  const auto stack = std::make_unique_for_overwrite<char[]>(kStack);
  const pid_t pid = ::clone(child_main, stack.get() + kStack, CLONE_VM | CLONE_VFORK | SIGCHLD, &start);
  ::pthread_sigmask(SIG_SETMASK, &start.mask, nullptr);
  return pid < 0 ? -1 : pid;
}

std::optional<int> wait_child(pid_t pid, std::chrono::milliseconds limit) {
  int status = 0;
  // A pidfd becomes readable when the child exits: one poll with the time
  // limit instead of a sleep loop.
  const int fd = int(::syscall(SYS_pidfd_open, pid, 0));
  if (fd >= 0) {
    pollfd p{fd, POLLIN, 0};
    int n;
    do n = ::poll(&p, 1, int(limit.count()));
    while (n < 0 && errno == EINTR);
    ::close(fd);
    if (n > 0 && ::waitpid(pid, &status, 0) == pid) return status;
  } else {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      if (::waitpid(pid, &status, WNOHANG) == pid) return status;
      ::usleep(2000);
    }
  }
  kill_child(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return std::nullopt;
}

void kill_child(pid_t pid, int sig) {
  ::kill(-pid, sig);
  ::kill(pid, sig);  // before it has made its group
}

std::string signal_name(int sig) {
  switch (sig) {
    case SIGSEGV:
      return "SIGSEGV";
    case SIGABRT:
      return "SIGABRT";
    case SIGKILL:
      return "SIGKILL";
    case SIGTERM:
      return "SIGTERM";
    case SIGBUS:
      return "SIGBUS";
    case SIGFPE:
      return "SIGFPE";
    case SIGILL:
      return "SIGILL";
    case SIGXCPU:
      return "SIGXCPU";
    case SIGXFSZ:
      return "SIGXFSZ";
    default:
      return "signal " + std::to_string(sig);
  }
}

bool ToolRun::ok() const { return status && WIFEXITED(*status) && WEXITSTATUS(*status) == 0; }

ToolRun run_tool(const std::vector<std::string>& argv, std::chrono::milliseconds limit) {
  ToolRun out;
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    out.output = "pipe failed";
    return out;
  }
  ChildOptions child;
  child.stdout_fd = fds[1];
  child.stderr_to_stdout = true;
  const pid_t pid = spawn_child(argv, child);
  ::close(fds[1]);
  if (pid < 0) {
    ::close(fds[0]);
    out.output = "fork failed";
    return out;
  }
  const auto end = std::chrono::steady_clock::now() + limit;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    pollfd p{fds[0], POLLIN, 0};
    if (::poll(&p, 1, int(left.count())) < 0 && errno != EINTR) break;
    char buf[4096];
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n == 0) break;
    if (n > 0) out.output.append(buf, std::size_t(n));
  }
  ::close(fds[0]);
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
  out.status = wait_child(pid, std::max(left, std::chrono::milliseconds(1)));
  return out;
}

std::filesystem::path find_program(const std::string& name) {
  if (name.find('/') != std::string::npos) return name;
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  for (std::size_t at = 0; at <= dirs.size();) {
    const std::size_t colon = std::min(dirs.find(':', at), dirs.size());
    const std::filesystem::path p = std::filesystem::path(dirs.substr(at, colon - at)) / name;
    if (!p.parent_path().empty() && ::access(p.c_str(), X_OK) == 0) return p;
    at = colon + 1;
  }
  return {};
}

}  // namespace cgview::server
