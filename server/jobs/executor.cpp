#include "jobs/executor.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/errors.h"

namespace cgview::server {

WakePipe::WakePipe() {
  if (::pipe2(fds_, O_CLOEXEC | O_NONBLOCK) != 0) throw IoError("jobs: pipe failed");
}

WakePipe::~WakePipe() {
  ::close(fds_[0]);
  ::close(fds_[1]);
}

void WakePipe::wake() {
  const char c = 1;
  [[maybe_unused]] auto n = ::write(fds_[1], &c, 1);
}

void WakePipe::drain() {
  char buf[256];
  while (::read(fds_[0], buf, sizeof buf) > 0) {
  }
}

bool read_progress_lines(std::string& buffer, double& progress, std::string& stage) {
  bool found = false;
  for (std::size_t nl; (nl = buffer.find('\n')) != std::string::npos;) {
    const std::string line = buffer.substr(0, nl);
    buffer.erase(0, nl + 1);
    if (line.rfind("progress ", 0) != 0) continue;
    char* end = nullptr;
    const double f = std::strtod(line.c_str() + 9, &end);
    if (end == line.c_str() + 9 || std::isnan(f)) continue;
    progress = std::clamp(f, 0.0, 1.0);
    stage = *end == ' ' ? std::string(end + 1) : std::string();
    found = true;
  }
  // A worker that writes no newline must not grow the buffer without end.
  if (buffer.size() > 65536) buffer.clear();
  return found;
}

}  // namespace cgview::server
