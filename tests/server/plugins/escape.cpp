// A hostile plugin for the sandbox's test (tests/server/sandbox_test.cpp):
// each `attempt` tries one way out of a job.  One that works returns the
// metric "escaped" = 1; one the sandbox stops throws what the system said.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  std::string attempt = "read_file";
  std::string target;  // a path, or a port
  template <class V>
  void describe(V& v) {
    v.choice("attempt", attempt,
             {.label = "Attempt",
              .choices = {"read_file", "write_file", "connect_local", "connect_outside", "fork_bomb", "allocate",
                          "loop", "big_file", "segfault"}});
    v.text("target", target, {.label = "Target"});
  }
};

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what + ": " + std::strerror(errno)); }

AlgorithmResult escaped() { return {{{"escaped", Metrics{{"escaped", 1}}}}, {}}; }

AlgorithmResult run(const Mesh&, const Params& p, Context& ctx) {
  if (p.attempt == "read_file") {
    const int fd = ::open(p.target.c_str(), O_RDONLY);
    if (fd < 0) fail("cannot open " + p.target);
    char c;
    if (::read(fd, &c, 1) < 0) fail("cannot read " + p.target);
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
