#include "jobs/executor.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/errors.h"

namespace cgview::server {

Sandbox::Command sandboxed_worker(const Sandbox& sandbox, const LaunchSpec& job, const std::filesystem::path& worker,
                                  int slot, ChildOptions options, int spec_fd) {
  // The worker program is mounted where the job sees it where it lies
  // where the job may not walk (a wrapper script in a test's /tmp);
  // elsewhere it runs at its own path, one mount fewer.
  auto readable = job.read_only;
  std::string program = worker.string();
  if (!sandbox.shows_at_own_path(worker)) {
    program = std::string(kSandboxPrograms) + "/" + worker.filename().string();
    readable.push_back({worker, program});
  }
  if (spec_fd < 0) readable.push_back({job.dir / "job.json", kSandboxSpec});
  return sandbox.wrap({program, kSandboxSpec},
                      {.writable = job.work,
                       .readable = readable,
                       .hidden = {job.data_dir},
                       .visible = {worker.parent_path()},
                       .data_fd = spec_fd,
                       .data_at = spec_fd >= 0 ? kSandboxSpec : ""},
                      slot, std::move(options), Sandbox::Drop::by_program);
}

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

void ExecutorBase::cancel(const std::string& job_id) {
  {
    std::lock_guard lock(cancel_mutex_);
    cancels_.insert(job_id);
  }
  wake();
}

std::set<std::string> ExecutorBase::take_cancels() {
  std::set<std::string> cancels;
  std::lock_guard lock(cancel_mutex_);
  cancels.swap(cancels_);
  return cancels;
}

void ExecutorBase::watch(const std::string& job_id, double timeout_s) {
  if (timeout_s > 0)
    deadlines_[job_id] =
        std::chrono::steady_clock::now() +
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(timeout_s));
  else deadlines_.erase(job_id);
}

std::set<std::string> ExecutorBase::overdue() {
  std::set<std::string> over;
  const auto now = std::chrono::steady_clock::now();
  for (auto it = deadlines_.begin(); it != deadlines_.end();)
    if (now > it->second) over.insert(it->first), it = deadlines_.erase(it);
    else ++it;
  return over;
}

namespace {

// At most 60 bytes of what the worker wrote, unprintable bytes as '?'.
std::string quoted_output(std::string_view s) {
  std::string q = "\"";
  for (char c : s.substr(0, 60)) q += (c >= 0x20 && c < 0x7f) ? c : '?';
  return q + (s.size() > 60 ? "...\"" : "\"");
}

}  // namespace

ProgressRead read_progress_lines(std::string& buffer, double& progress, std::string& stage) {
  ProgressRead r;
  const std::string said = "the worker wrote something other than progress on its progress pipe: ";
  for (std::size_t nl; (nl = buffer.find('\n')) != std::string::npos;) {
    const std::string line = buffer.substr(0, nl);
    buffer.erase(0, nl + 1);
    if (line.size() > kMaxProgressLine) {
      r.garbage = said + "a line of " + std::to_string(line.size()) + " bytes";
      break;
    }
    if (line.rfind("progress ", 0) != 0) {
      r.garbage = said + quoted_output(line);
      break;
    }
    char* end = nullptr;
    const double f = std::strtod(line.c_str() + 9, &end);
    if (end == line.c_str() + 9 || !std::isfinite(f) || (*end != ' ' && *end != '\0')) {
      r.garbage = said + quoted_output(line);
      break;
    }
    progress = std::clamp(f, 0.0, 1.0);
    stage = *end == ' ' ? std::string(end + 1) : std::string();
    r.found = true;
  }
  // A worker that writes no newline must not grow the buffer without end.
  if (r.garbage.empty() && buffer.size() > kMaxProgressLine)
    r.garbage = said + std::to_string(buffer.size()) + " bytes without a line end";
  if (!r.garbage.empty()) buffer.clear();
  return r;
}

}  // namespace cgview::server
