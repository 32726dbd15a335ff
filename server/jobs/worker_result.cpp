#include "jobs/worker_result.h"

#include <csignal>
#include <cstdio>

#include "child_process.h"
#include "io/parse_json.h"
#include "jobs/job_files.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  return s;
}

// A report's text, its first kMaxReportBytes; a report that cannot be
// taken (a link, a FIFO) is said in *refused.
std::string report(const JobDir& dir, const std::string& name, std::string* refused) {
  std::string why;
  const auto text = dir.read(name, kMaxReportBytes, &why, true);
  if (!text && !why.empty() && refused->empty()) *refused = why;
  return text ? trimmed(*text) : "";
}

}  // namespace

WorkerOutcome read_worker_outcome(const JobDir& work, const JobDir& run, const WorkerEnd& end,
                                  const WorkerLimits& limits) {
  using How = WorkerEnd::How;
  WorkerOutcome out;
  std::string refused;
  std::string text = report(work, "error.txt", &refused);
  if (text.empty()) text = report(run, "stderr.txt", &refused);
  const bool exited_ok = end.how == How::exited && end.code == 0;
  const bool oom_report = (end.how == How::exited && end.code == 3) || text.find("bad_alloc") != std::string::npos;
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%g", limits.timeout_s);
  std::string result_why;
  const auto result_text =
      exited_ok ? work.read("result.json", kMaxResultJsonBytes, &result_why) : std::optional<std::string>();
  if (end.how == How::garbled || end.how == How::not_started) {
    out.error = end.detail;
  } else if (end.how == How::timed_out) {
    out.error = std::string("exceeded its time limit of ") + seconds + " s";
  } else if (exited_ok && !result_why.empty()) {
    out.error = "the worker's result was refused: " + result_why;
  } else if (exited_ok && result_text) {
    const json result = parse_json_or_discarded(*result_text);
    const std::string broken =
        result.is_object() ? incomplete_artifact(work, result.value("artifacts", json()), limits.result_bytes) : "";
    if (!result.is_object()) {
      out.error = "the worker wrote an unreadable result";
    } else if (!broken.empty()) {
      out.error = "the worker's results are incomplete: " + broken;
    } else {
      out.done = true;
      out.artifacts = result.value("artifacts", json::array());
      for (const auto& w : result.value("warnings", json::array()))
        if (w.is_string()) out.warnings.push_back(w);
    }
  } else if (end.how == How::out_of_memory || (oom_report && limits.memory_mb > 0)) {
    out.error = "exceeded its memory limit of " + std::to_string(limits.memory_mb) + " MB";
  } else if (end.how == How::exited && end.code == 4) {
    out.error = "the server's storage is full: the job's results could not be written";
  } else if (end.how == How::signaled && end.signal == SIGXFSZ && limits.file_mb > 0) {
    out.error = "wrote a file over its file-size limit of " + std::to_string(limits.file_mb) + " MB";
  } else if (end.how == How::signaled) {
    out.error = "killed by signal " + signal_name(end.signal);
  } else if (end.how == How::node_failed) {
    out.error = "the node it ran on failed" + (end.detail.empty() ? std::string() : " (" + end.detail + ")");
  } else if (end.how == How::lost) {
    out.error = end.detail.empty() ? "its executor lost it" : end.detail;
  } else if (end.how == How::exited && end.code == 127 && text.empty()) {
    out.error = "the worker could not be started";
  } else {
    out.error = text.empty() ? "the worker exited with status " + std::to_string(end.code) : text;
  }
  if (!out.done && !refused.empty()) out.error += " (" + refused + ")";
  // What the system answered inside the sandbox, said as the rule it met.
  if (!out.done && limits.sandboxed) {
    const std::pair<const char*, std::string> hints[] = {
        {"Read-only file system", "the sandbox: a job writes only in its own directory"},
        {"Network is unreachable", "the sandbox: a job has no network"},
        {"Connection refused", "the sandbox: a job has no network"},
        {"Resource temporarily unavailable",
         "the sandbox's process limit: " + std::to_string(limits.processes) + " processes and threads"},
        {"No such file or directory", "the sandbox: the server's data and other jobs are not visible to a job"},
        {"Permission denied", "the sandbox: a job reads only its inputs"},
    };
    for (const auto& [what, hint] : hints)
      if (out.error.find(what) != std::string::npos) {
        out.error += " (" + hint + ")";
        break;
      }
  }
  return out;
}

}  // namespace cgview::server
