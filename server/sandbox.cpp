#include "sandbox.h"

#include <fcntl.h>
#include <grp.h>
#include <linux/capability.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/errors.h"

namespace cgview::server {

namespace fs = std::filesystem;

namespace {

// The read-only system, fresh /dev and /proc, an empty /run to mount the
// job's files under, and namespaces of its own (the network's included: no
// socket reaches the server or the outside).  A root server's bwrap is
// privileged and makes no user namespace: setpriv (or the worker itself,
// Drop::by_program) then drops the job to its own user, with no
// capabilities left.  `jobs_dev`: the mount namespace the bubblewraps start
// in has the jobs' /dev already (jobs_dev_nodes), bound whole, devices
// allowed, instead of the /dev bubblewrap makes for each run.
std::vector<std::string> base_args(const fs::path& bwrap, bool root, bool jobs_dev) {
  std::vector<std::string> a = {bwrap.string(), "--ro-bind", "/", "/"};
  if (jobs_dev) a.insert(a.end(), {"--dev-bind", "/dev", "/dev"});
  else a.insert(a.end(), {"--dev", "/dev"});
  a.insert(a.end(), {"--proc", "/proc", "--tmpfs", "/run", "--perms", "0755", "--dir", "/run/cgview",
                     "--die-with-parent", "--new-session"});
  if (root)
    a.insert(a.end(), {"--unshare-ipc", "--unshare-pid", "--unshare-net", "--unshare-uts", "--unshare-cgroup-try"});
  else a.insert(a.end(), {"--unshare-all", "--cap-drop", "ALL"});
  return a;
}

std::vector<std::string> drop_to(const fs::path& setpriv, long id) {
  const std::string n = std::to_string(id);
  return {setpriv.string(),  "--reuid=" + n,        "--regid=" + n,  "--clear-groups",
          "--inh-caps=-all", "--bounding-set=-all", "--no-new-privs"};
}

// Whether `path` lies where the sandbox shows something else than the
// system's own: its /tmp (the job's), /run, /dev and /proc.
bool under_replaced(const fs::path& path) {
  for (const char* r : {"/tmp", "/run", "/dev", "/proc"})
    if (path == r || path.string().starts_with(std::string(r) + "/")) return true;
  return false;
}

// /proc/self/status by name ("Uid" -> "0 0 0 0", "CapEff" -> 16 hex
// digits): what the kernel says the process is and holds.
std::map<std::string, std::string> status_lines() {
  std::map<std::string, std::string> lines;
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (const auto colon = line.find(':'); colon != std::string::npos) {
      std::string value = line.substr(colon + 1);
      for (char& ch : value)
        if (ch == '\t') ch = ' ';
      value.erase(0, value.find_first_not_of(' '));
      value.erase(value.find_last_not_of(' ') + 1);
      lines[line.substr(0, colon)] = value;
    }
  return lines;
}

// A mount point of /proc/self/mountinfo, its octal escapes ("\040") undone.
std::string unescaped(const std::string& field) {
  auto octal = [](char c) { return c >= '0' && c <= '7'; };
  std::string s;
  for (std::size_t i = 0; i < field.size(); ++i)
    if (field[i] == '\\' && i + 3 < field.size() && octal(field[i + 1]) && octal(field[i + 2]) && octal(field[i + 3])) {
      s += char((field[i + 1] - '0') * 64 + (field[i + 2] - '0') * 8 + (field[i + 3] - '0'));
      i += 3;
    } else {
      s += field[i];
    }
  return s;
}

// The mounts a job's sandbox does without, in the order to undo them (the
// last made first): every one below /proc and /sys (the control groups,
// binfmt_misc, tracing: the job's /proc is its own, and it reads /sys only
// for what the kernel puts there itself), and below /dev the terminals,
// message queues and huge pages (bubblewrap makes the job's /dev anew from
// the devices themselves).  No user's data lives on those.
std::vector<std::string> mounts_jobs_do_without() {
  std::vector<std::string> drop;
  std::ifstream f("/proc/self/mountinfo");
  for (std::string line; std::getline(f, line);) {
    std::istringstream in(line);
    std::string id, parent, device, root, point, field;
    in >> id >> parent >> device >> root >> point;
    while (in >> field && field != "-") {
    }
    std::string type;
    in >> type;
    point = unescaped(point);
    const bool below_proc_sys = point.starts_with("/proc/") || point.starts_with("/sys/");
    const bool dev_pseudo = point.starts_with("/dev/") && (type == "devpts" || type == "mqueue" || type == "hugetlbfs");
    if (below_proc_sys || dev_pseudo) drop.push_back(point);
  }
  std::reverse(drop.begin(), drop.end());
  return drop;
}

// In a mount namespace of the server's making (slim_mount_namespace's
// child, system calls only): a /dev of the devices bubblewrap's --dev gives
// a job (null, zero, full, random, urandom, tty; the same device numbers),
// its links, and an empty shm/ and pts/, on a tmpfs made read-only for all
// (root included: no job may write where the others read).  bubblewrap
// then binds it in one mount and one read of the mount table where --dev
// makes a tmpfs, binds each device (a read of the mount table each) and
// mounts a devpts: ~0.5 ms of each run's CPU.  Jobs get no pseudo-terminal
// (they run with none).  False, and the system's /dev left as it was,
// where any step fails.
bool jobs_dev_nodes() {
  if (::mount("tmpfs", "/dev", "tmpfs", MS_NOSUID | MS_NOEXEC, "mode=0755,size=64k,nr_inodes=64") != 0) return false;
  ::umask(0);
  struct Node {
    const char* path;
    unsigned major, minor;
  };
  static constexpr Node kNodes[] = {{"/dev/null", 1, 3},   {"/dev/zero", 1, 5},    {"/dev/full", 1, 7},
                                    {"/dev/random", 1, 8}, {"/dev/urandom", 1, 9}, {"/dev/tty", 5, 0}};
  static constexpr const char* kLinks[][2] = {{"/proc/self/fd", "/dev/fd"},       {"/proc/self/fd/0", "/dev/stdin"},
                                              {"/proc/self/fd/1", "/dev/stdout"}, {"/proc/self/fd/2", "/dev/stderr"},
                                              {"/proc/kcore", "/dev/core"},       {"pts/ptmx", "/dev/ptmx"}};
  bool ok = true;
  for (const Node& n : kNodes) ok = ok && ::mknod(n.path, S_IFCHR | 0666, makedev(n.major, n.minor)) == 0;
  for (const auto& l : kLinks) ok = ok && ::symlink(l[0], l[1]) == 0;
  ok = ok && ::mkdir("/dev/shm", 0755) == 0 && ::mkdir("/dev/pts", 0755) == 0;
  ok = ok && ::mount(nullptr, "/dev", nullptr, MS_REMOUNT | MS_RDONLY | MS_NOSUID | MS_NOEXEC, nullptr) == 0;
  if (!ok) ::umount2("/dev", MNT_DETACH);
  return ok;
}

// A mount namespace like the server's less `drop`, kept by the descriptor
// returned (-1 where it cannot be made: the server's own is used), with
// the jobs' /dev (jobs_dev_nodes) where `jobs_dev` comes back true.  A
// child makes it and goes; mounts the system makes later still reach it (a
// slave of the server's), and nothing done in it reaches the system.
int slim_mount_namespace(const std::vector<std::string>& drop, bool& jobs_dev) {
  int ready[2], done[2];
  if (::pipe2(ready, O_CLOEXEC) != 0) return -1;
  if (::pipe2(done, O_CLOEXEC) != 0) {
    ::close(ready[0]);
    ::close(ready[1]);
    return -1;
  }
  const pid_t pid = ::fork();
  if (pid == 0) {
    // Only system calls here, the paths made before the fork.  Not one
    // mount is undone unless the namespace is the child's own and a slave.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    ::close(ready[0]);
    ::close(done[1]);  // the server's: its end is the child's cue to go
    if (::unshare(CLONE_NEWNS) != 0 || ::mount(nullptr, "/", nullptr, MS_REC | MS_SLAVE, nullptr) != 0) ::_exit(1);
    for (const std::string& p : drop) ::umount2(p.c_str(), MNT_DETACH);
    if (::write(ready[1], jobs_dev_nodes() ? "d" : "1", 1) != 1) ::_exit(1);
    char c;
    while (::read(done[0], &c, 1) < 0 && errno == EINTR) {
    }
    ::_exit(0);
  }
  ::close(ready[1]);
  ::close(done[0]);
  int fd = -1;
  char c;
  ssize_t n;
  do n = ::read(ready[0], &c, 1);
  while (n < 0 && errno == EINTR);
  jobs_dev = n == 1 && c == 'd';
  if (pid > 0 && n == 1) fd = ::open(("/proc/" + std::to_string(pid) + "/ns/mnt").c_str(), O_RDONLY | O_CLOEXEC);
  ::close(ready[0]);
  ::close(done[1]);
  if (pid > 0) ::waitpid(pid, nullptr, 0);
  return fd;
}

}  // namespace

void drop_to_job_user(long id) {
  auto fail = [](const std::string& what) {
    throw IoError("cannot drop to the job's user: " + what + ": " + std::strerror(errno));
  };
  errno = 0;
  if (status_lines()["Threads"] != "1") fail("more than one thread");
  if (::prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0) fail("no_new_privs");
  // Every capability out of the bounding set, up to the kernel's last (EINVAL past it).
  for (int cap = 0;; ++cap)
    if (::prctl(PR_CAPBSET_DROP, cap, 0, 0, 0) != 0) {
      if (errno == EINVAL && cap > 0) break;
      fail("bounding set");
    }
  if (::setgroups(0, nullptr) != 0) fail("groups");
  if (::setresgid(gid_t(id), gid_t(id), gid_t(id)) != 0) fail("group");
  // From root to another user: the permitted, effective and ambient sets are emptied; the inheritable below.
  if (::setresuid(uid_t(id), uid_t(id), uid_t(id)) != 0) fail("user");
  __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct none[_LINUX_CAPABILITY_U32S_3] = {};
  if (::syscall(SYS_capset, &header, none) != 0) fail("capabilities");
  // As after setpriv's exec of it: the change of user made it undumpable
  // (its /proc files root's, no core file), which a program exec'd as that
  // user is not.
  if (::prctl(PR_SET_DUMPABLE, 1, 0, 0, 0) != 0) fail("dumpable");
  // What the kernel says now, as a test of the job's would read it.
  auto status = status_lines();
  const std::string n = std::to_string(id), ids = n + " " + n + " " + n + " " + n, zero(16, '0');
  for (const char* key : {"Uid", "Gid"})
    if (status[key] != ids) errno = EPERM, fail(std::string(key) + " is " + status[key]);
  for (const char* key : {"CapInh", "CapPrm", "CapEff", "CapBnd", "CapAmb"})
    if (status[key] != zero) errno = EPERM, fail(std::string(key) + " is " + status[key]);
  if (status["Groups"] != "" || status["NoNewPrivs"] != "1") errno = EPERM, fail("groups or no_new_privs left");
}

Sandbox::Sandbox(SandboxConfig config, fs::path bwrap) : config_(std::move(config)), bwrap_(std::move(bwrap)) {
  if (config_.mode == "off") {
    why_not_ = "the sandbox is off (sandbox.mode)";
    return;
  }
  if (bwrap_.empty()) bwrap_ = find_program("bwrap");
  if (bwrap_.empty()) {
    why_not_ = "bubblewrap (bwrap) is not installed";
    return;
  }
  const bool root = ::geteuid() == 0;
  if (!root) prlimit_ = find_program("prlimit");
  if (root && (setpriv_ = find_program("setpriv")).empty()) {
    why_not_ = "setpriv (util-linux) is not installed";
    return;
  }
  if (root) mount_ns_ = slim_mount_namespace(mounts_jobs_do_without(), jobs_dev_);
  // A real run, as a worker would start, tells whether this machine allows
  // it: an empty output where it does, else what bubblewrap said.
  auto probe = [&]() -> std::optional<std::string> {
    std::vector<std::string> argv = base_args(bwrap_, root, jobs_dev_);
    argv.push_back("--");
    if (root) {
      auto d = drop_to(setpriv_, config_.uid_base);
      argv.insert(argv.end(), d.begin(), d.end());
    }
    argv.push_back("/bin/true");
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return "pipe failed";
    ChildOptions o;
    o.stdout_fd = fds[1];
    o.stderr_to_stdout = true;
    o.mount_ns_fd = mount_ns_;
    const pid_t pid = spawn_child(argv, o);
    ::close(fds[1]);
    std::string out;
    char buf[1024];
    for (ssize_t n; pid > 0 && (n = ::read(fds[0], buf, sizeof buf)) > 0;) out.append(buf, std::size_t(n));
    ::close(fds[0]);
    const auto status = pid > 0 ? wait_child(pid, std::chrono::seconds(10)) : std::nullopt;
    if (status && WIFEXITED(*status) && WEXITSTATUS(*status) == 0) return std::nullopt;
    return out;
  };
  auto failed = probe();
  if (failed && jobs_dev_) {  // a bubblewrap that will not bind it: the /dev it makes, as before
    jobs_dev_ = false;
    failed = probe();
  }
  enabled_ = !failed;
  if (!enabled_) {
    std::string out = *failed;
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    why_not_ = "bubblewrap cannot start here" + (out.empty() ? std::string() : ": " + out);
  }
}

Sandbox::~Sandbox() {
  if (mount_ns_ >= 0) ::close(mount_ns_);
}

Sandbox::Command Sandbox::wrap(const std::vector<std::string>& argv, const SandboxMounts& mounts, int slot,
                               ChildOptions options, Drop drop) const {
  Command c;
  c.options = std::move(options);
  if (!enabled_) {
    c.argv = argv;
    return c;
  }
  c.options.processes = config_.processes;
  c.options.file_mb = config_.file_mb;
  c.options.mount_ns_fd = mount_ns_;
  const bool root = ::geteuid() == 0;
  const long uid = config_.uid_base + slot;
  c.argv = base_args(bwrap_, root, jobs_dev_);
  std::error_code ec;
  // The directories above each mount under /run/cgview, walkable by the job's user.
  std::set<std::string> dirs;
  auto parents = [&](const std::string& inside) {
    for (fs::path d = fs::path(inside).parent_path(); d.string().size() > std::string("/run/cgview").size();
         d = d.parent_path())
      dirs.insert(d.string());
  };
  for (const auto& [file, inside] : mounts.readable) parents(inside);
  parents(kSandboxJob);
  if (mounts.data_fd >= 0) parents(mounts.data_at);
  for (const std::string& d : dirs) c.argv.insert(c.argv.end(), {"--perms", "0755", "--dir", d});
  for (const auto& [file, inside] : mounts.readable) c.argv.insert(c.argv.end(), {"--ro-bind", file.string(), inside});
  if (mounts.data_fd >= 0) {
    // Readable by the job's user (bubblewrap, root here, makes the file).
    c.options.data_fd = mounts.data_fd;
    c.argv.insert(c.argv.end(), {"--perms", "0444", "--ro-bind-data", std::to_string(kChildDataFd), mounts.data_at});
  }
  if (!mounts.writable.empty()) {
    // The job's /tmp is its own directory, shown there too: what it leaves
    // there counts as its files do (a tmpfs would be memory no limit
    // holds), and no directory more is made and removed for each run (on
    // ext4 without a journal, each new one is a scan past the inodes freed
    // in the last minutes).
    if (root) {
      if (::chown(mounts.writable.c_str(), uid_t(uid), gid_t(uid)) != 0)
        throw IoError("cannot give " + mounts.writable.string() + " to the sandbox's user: " + std::strerror(errno));
      for (const auto& e : fs::directory_iterator(mounts.writable, ec))
        (void)::chown(e.path().c_str(), uid_t(uid), gid_t(uid));
    }
    c.argv.insert(c.argv.end(), {"--bind", mounts.writable.string(), kSandboxJob, "--bind", mounts.writable.string(),
                                 "/tmp", "--chdir", kSandboxJob});
  }
  // After /tmp: a build tree under /tmp (a CI's clone) keeps its programs and headers.
  // (Once each: the worker's directory is most often the server's own.)
  std::set<fs::path> visible(mounts.visible.begin(), mounts.visible.end());
  visible.insert(config_.visible.begin(), config_.visible.end());
  for (const fs::path& v : visible) {
    const auto at = v.empty() ? std::nullopt : place(v);
    // Elsewhere the read-only root shows it already: a mount of its own
    // would cost bubblewrap a mount and a read of the whole mount table
    // (those reads were 40% of its CPU).
    if (!at || !at->replaced) continue;
    // Under the job's /tmp, the directories above it are made anew: walkable
    // by the job's user (bwrap would make them 0700).
    std::vector<std::string> above;
    for (fs::path d = v.parent_path(); d.string().starts_with("/tmp/"); d = d.parent_path())
      above.push_back(d.string());
    for (auto d = above.rbegin(); d != above.rend(); ++d) c.argv.insert(c.argv.end(), {"--perms", "0755", "--dir", *d});
    c.argv.insert(c.argv.end(), {"--ro-bind", v.string(), v.string()});
  }
  // Hidden last: no mount above may show the data directory again.
  std::vector<fs::path> hidden = mounts.hidden;
  hidden.insert(hidden.end(), config_.hidden.begin(), config_.hidden.end());
  for (const fs::path& h : hidden) {
    if (h.empty() || !fs::exists(h, ec)) continue;
    if (fs::is_directory(h, ec)) c.argv.insert(c.argv.end(), {"--tmpfs", h.string(), "--remount-ro", h.string()});
    else c.argv.insert(c.argv.end(), {"--ro-bind", "/dev/null", h.string()});
  }

  if (root && drop == Drop::by_program) {
    // Until it drops, the program holds only what dropping takes, and the
    // job's files (bwrap would leave a root sandbox's first process every
    // capability): a wrapper script given as the worker, which runs as root
    // around it, cannot remount or reach past the sandbox's mounts either.
    c.argv.insert(c.argv.end(), {"--cap-drop", "ALL", "--cap-add", "CAP_SETUID", "--cap-add", "CAP_SETGID", "--cap-add",
                                 "CAP_SETPCAP", "--cap-add", "CAP_DAC_OVERRIDE", "--setenv", kJobUserVariable,
                                 std::to_string(uid), "--"});
    c.argv.insert(c.argv.end(), argv.begin(), argv.end());
    return c;
  }
  c.argv.push_back("--");
  if (root) {
    const auto d = drop_to(setpriv_, uid);
    c.argv.insert(c.argv.end(), d.begin(), d.end());
  } else if (!prlimit_.empty() && c.options.processes > 0) {
    c.argv.insert(c.argv.end(), {prlimit_.string(), "--nproc=" + std::to_string(c.options.processes), "--"});
    c.options.processes = 0;  // not before bubblewrap: see prlimit_
  }
  c.argv.insert(c.argv.end(), argv.begin(), argv.end());
  return c;
}

std::optional<Sandbox::Place> Sandbox::place(const fs::path& path) const {
  {
    std::lock_guard lock(places_mutex_);
    if (const auto it = places_.find(path); it != places_.end()) return it->second;
  }
  // Not remembered while it does not exist (a precompiled header's
  // directory made later).
  std::error_code ec;
  const fs::path real = fs::canonical(path, ec);
  if (ec) return std::nullopt;
  Place p;
  p.replaced = under_replaced(real);
  p.open_to_all = true;
  for (fs::path d = real;; d = d.parent_path()) {
    struct stat st {};
    if (::stat(d.c_str(), &st) != 0 || !(st.st_mode & S_IXOTH)) p.open_to_all = false;
    if (d == d.root_path() || !p.open_to_all) break;
  }
  std::lock_guard lock(places_mutex_);
  places_[path] = p;
  return p;
}

bool Sandbox::shows_at_own_path(const fs::path& path) const {
  const auto p = place(path);
  return p && !p->replaced && p->open_to_all;
}

std::optional<long> Sandbox::job_user(int slot) const {
  if (!enabled_ || ::geteuid() != 0) return std::nullopt;
  return config_.uid_base + slot;
}

Sandbox::Slot& Sandbox::Slot::operator=(Slot&& o) noexcept {
  if (this != &o) {
    give_back();
    held_ = std::move(o.held_);
    number_ = o.number_;
  }
  return *this;
}

void Sandbox::Slot::give_back() {
  if (!held_) return;
  std::lock_guard lock(held_->mutex);
  held_->numbers.erase(number_);
  held_.reset();
}

Sandbox::Slot Sandbox::take_slot() const {
  Slot s;
  std::lock_guard lock(slots_->mutex);
  int n = 0;
  while (slots_->numbers.count(n)) ++n;
  slots_->numbers.insert(n);
  s.held_ = slots_;
  s.number_ = n;
  return s;
}

}  // namespace cgview::server
