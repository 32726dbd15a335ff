// A hostile plugin for the sandbox's tests (tests/server/plugins_test.cpp,
// tests/server/job_boundary_test.cpp, tests/slurm): each `attempt` tries
// one way out of a job.  One that works returns the metric "escaped" = 1;
// one the sandbox stops throws what the system said.  The attempts on the
// server's side of the boundary leave something in the job's directory for
// the server to follow (a link, a FIFO, a huge result) and end the worker
// at once, as a plugin may, before the worker writes its own report.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  std::string attempt = "read_file";
  std::string target;  // a path, or a port
  template <class V>
  void describe(V& v) {
    v.choice(
        "attempt", attempt,
        {.label = "Attempt",
         .choices = {"read_file",  "write_file",  "connect_local",  "connect_outside", "fork_bomb",     "allocate",
                     "loop",       "big_file",    "segfault",       "link_error",      "link_artifact", "fifo_error",
                     "zero_error", "huge_result", "many_artifacts", "many_files",      "link_tmp",      "read_env",
                     "link_exit",  "fill_disk",   "become_root"}});
    v.text("target", target, {.label = "Target"});
  }
};

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what + ": " + std::strerror(errno)); }

AlgorithmResult escaped() { return {{{"escaped", Metrics{{"escaped", 1}}}}, {}}; }

// A result.json listing `count` text artifacts, each the file `file` of `bytes` bytes.
void write_result(std::size_t count, const std::string& file, long bytes) {
  std::ofstream r("result.json");
  r << "{\"artifacts\":[";
  for (std::size_t k = 0; k < count; ++k)
    r << (k ? "," : "") << "{\"name\":\"a" << k << "\",\"kind\":\"text\",\"file\":\"" << file
      << "\",\"bytes\":" << bytes << "}";
  r << "],\"warnings\":[]}";
}

AlgorithmResult run(const Mesh&, const Params& p, Context& ctx) {
  // The server's side: what it reads of the job's directory once the worker is gone.
  if (p.attempt == "link_error" || p.attempt == "zero_error") {
    if (::symlink(p.attempt == "zero_error" ? "/dev/zero" : p.target.c_str(), "error.txt") != 0) fail("symlink");
    ::_exit(1);
  }
  if (p.attempt == "link_exit") {
    // Where a batch script once wrote the worker's exit status and output,
    // as the server's user, after the sandbox: links to the target.
    for (const char* name : {"worker.exit", "worker.exit.tmp", "worker.exit.0", "worker.exit.tmp.0", "stdout.0",
                             "stdout.txt", "stderr.txt"})
      if (::symlink(p.target.c_str(), name) != 0) fail(std::string("symlink ") + name);
    ::_exit(0);
  }
  if (p.attempt == "fifo_error") {
    if (::mkfifo("error.txt", 0644) != 0) fail("mkfifo");
    ::_exit(1);
  }
  if (p.attempt == "link_artifact") {
    // target: "PATH SIZE", the size the file outside has, so that the list matches it.
    const auto space = p.target.rfind(' ');
    if (::symlink(p.target.substr(0, space).c_str(), "stolen.txt") != 0) fail("symlink");
    write_result(1, "stolen.txt", std::stol(p.target.substr(space + 1)));
    ::_exit(0);
  }
  if (p.attempt == "huge_result") {
    std::ofstream("one.txt") << "x";
    write_result(200000, "one.txt", 1);  // about 12 MB of JSON
    ::_exit(0);
  }
  if (p.attempt == "many_artifacts") {
    std::ofstream("one.txt") << "x";
    write_result(1000, "one.txt", 1);
    ::_exit(0);
  }
  if (p.attempt == "many_files") {
    const int n = p.target.empty() ? 20000 : std::stoi(p.target);
    for (int k = 0; k < n; ++k) {
      const int fd = ::open(("f" + std::to_string(k)).c_str(), O_WRONLY | O_CREAT, 0644);
      if (fd < 0) fail("cannot create file " + std::to_string(k));
      ::close(fd);
    }
    // Then it waits to be stopped, for the server's bound to be met while it runs.
    for (;;) ::pause();
  }
  if (p.attempt == "fill_disk") {
    // Files of 1 MB, each under the file-size limit, `target` MB of them
    // (400, more than any quota, by default): then wait to be stopped.
    const std::vector<char> block(1 << 20, 'x');
    const int megabytes = p.target.empty() ? 400 : std::stoi(p.target);
    for (int k = 0; k < megabytes; ++k) {
      std::ofstream f("fill" + std::to_string(k), std::ios::binary);
      if (!f.write(block.data(), std::streamsize(block.size()))) fail("cannot write fill" + std::to_string(k));
    }
    for (;;) ::pause();
  }
  if (p.attempt == "link_tmp") {
    // A run that sees the server's data as its /tmp has escaped; any other
    // puts a link named tmp in its directory (where a tmp/ there was its
    // /tmp, in its place), for a later run to be given as its /tmp, and
    // waits to be stopped.
    for (const char* server_side : {"/tmp/cgview.db", "/tmp/jobs", "/tmp/runs", "/tmp/job.json", "/tmp/work"})
      if (::access(server_side, F_OK) == 0) return escaped();
    if (::access("tmp", F_OK) == 0 && ::rename("tmp", "tmp.old") != 0 && ::rmdir("tmp") != 0) fail("cannot move tmp");
    if (::symlink(p.target.empty() ? "../../.." : p.target.c_str(), "tmp") != 0) fail("symlink");
    for (;;) ::pause();
  }
  if (p.attempt == "become_root") {
    if (::setuid(0) == 0 || ::setgid(0) == 0) return escaped();
    // What the kernel says the job holds, for the test to read in its error.
    std::string held = std::string("cannot become root: ") + std::strerror(errno) + ";";
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
      if (line.starts_with("Cap") || line.starts_with("NoNewPrivs:")) held += " " + line;
    std::replace(held.begin(), held.end(), '\t', ' ');
    throw std::runtime_error(held);
  }
  if (p.attempt == "read_env") {
    for (char** e = ::environ; *e; ++e)
      if (std::string(*e).find(p.target) != std::string::npos) return escaped();
    throw std::runtime_error("no variable names " + p.target);
  }
  if (p.attempt == "read_file") {
    const int fd = ::open(p.target.c_str(), O_RDONLY);
    if (fd < 0) fail("cannot open " + p.target);
    char c;
    const ssize_t n = ::read(fd, &c, 1);
    if (n < 0) fail("cannot read " + p.target);
    // A file the sandbox hides behind /dev/null opens, and holds nothing.
    if (n == 0) throw std::runtime_error("read nothing from " + p.target);
    return escaped();
  }
  if (p.attempt == "write_file") {
    const int fd = ::open(p.target.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) fail("cannot create " + p.target);
    return escaped();
  }
  if (p.attempt == "connect_local" || p.attempt == "connect_outside") {
    const int s = ::socket(AF_INET, SOCK_STREAM, 0);
    if (s < 0) fail("cannot make a socket");
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(p.attempt == "connect_local" ? std::stoi(p.target) : 80);
    ::inet_pton(AF_INET, p.attempt == "connect_local" ? "127.0.0.1" : "1.1.1.1", &a.sin_addr);
    if (::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) fail("cannot connect");
    return escaped();
  }
  if (p.attempt == "fork_bomb") {
    for (int n = 0; n < 100000; ++n) {
      const pid_t pid = ::fork();
      if (pid < 0) fail("fork failed after " + std::to_string(n) + " processes");
      if (pid == 0) {
        ::pause();
        ::_exit(0);
      }
    }
    return escaped();
  }
  if (p.attempt == "allocate") {
    std::vector<char> big(std::size_t(10) << 30);  // 10 GB
    std::memset(big.data(), 1, big.size());
    return escaped();
  }
  if (p.attempt == "loop") {
    for (;;) __asm__ volatile("");
  }
  if (p.attempt == "big_file") {
    std::ofstream f("big.bin", std::ios::binary);
    std::vector<char> block(1 << 20, 'x');
    for (int i = 0; i < 10 * 1024 && f; ++i) f.write(block.data(), std::streamsize(block.size()));
    if (!f) fail("cannot write big.bin");
    return escaped();
  }
  if (p.attempt == "segfault") {
    volatile int* nowhere = nullptr;
    *nowhere = 1;
  }
  (void)ctx;
  throw InvalidInput("no such attempt");
}

CGVIEW_REGISTER_ALGORITHM(escape, Params, run,
                          {.title = "Escape",
                           .description = "Tries a way out of the sandbox.",
                           .area = "test",
                           .outputs = {{"escaped", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
