#include "jobs/slurm_executor.h"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "child_process.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "jobs/job_files.h"

namespace cgview::server {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::chrono::seconds kToolLimit{30};
// How long a job whose newest run ended may stay held before it is settled from that run.
constexpr std::chrono::seconds kHeldWithAResult{10};

// Slurm's states after which a job runs no more.
bool final_state(const std::string& s) {
  return s == "COMPLETED" || s == "FAILED" || s == "CANCELLED" || s == "TIMEOUT" || s == "OUT_OF_MEMORY" ||
         s == "NODE_FAIL" || s == "PREEMPTED" || s == "BOOT_FAIL" || s == "DEADLINE" || s == "SPECIAL_EXIT" ||
         s == "REVOKED";
}

// A shell word: 'text' with each ' written '\''.
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::size_t at = 0;
  for (std::size_t k; (k = s.find(sep, at)) != std::string::npos; at = k + 1) out.push_back(s.substr(at, k - at));
  out.push_back(s.substr(at));
  return out;
}

// KEY=VALUE of `scontrol show job -o` ("" when absent).
std::string field(const std::string& line, const std::string& key) {
  for (const std::string& word : split(line, ' '))
    if (word.rfind(key + "=", 0) == 0) return word.substr(key.size() + 1);
  return "";
}

std::string first_line(std::string s) {
  if (const auto nl = s.find('\n'); nl != std::string::npos) s.resize(nl);
  return s;
}

// The newest run's file `stem`.N in a run's directory ("" when none): a
// job Slurm requeued runs again as run N+1 (SLURM_RESTART_COUNT), and an
// earlier run still going on a failed node writes only its own.
std::string newest_run_file(const fs::path& dir, const std::string& stem) {
  std::string best;
  long best_n = -1;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (!name.starts_with(stem + ".")) continue;
    const std::string n = name.substr(stem.size() + 1);
    if (n.empty() || n.size() > 6 || n.find_first_not_of("0123456789") != std::string::npos) continue;
    if (std::stol(n) > best_n) best_n = std::stol(n), best = name;
  }
  return best;
}

// The exit status file of the newest run that started (its started.N),
// "" while it has none; where no run says it started (a node without the
// data directory sends worker.exit back), the newest there is.
std::string newest_exit_file(const fs::path& dir) {
  const std::string started = newest_run_file(dir, "started");
  if (started.empty()) return newest_run_file(dir, "worker.exit");
  const std::string exit = "worker.exit" + started.substr(std::string("started").size());
  std::error_code ec;
  return fs::is_regular_file(dir / exit, ec) ? exit : "";
}

}  // namespace

SlurmExecutor::SlurmExecutor(SlurmConfig config, fs::path worker, std::shared_ptr<const Sandbox> sandbox,
                             std::size_t memory_mb)
    : config_(std::move(config)), sandbox_(std::move(sandbox)), worker_(std::move(worker)) {
  if (!config_.worker.empty()) worker_ = config_.worker;
  if (config_.max_jobs < 1) config_.max_jobs = 1;
  if (config_.max_pending < 1) config_.max_pending = 1;
  if (!(config_.poll_s > 0)) config_.poll_s = 1;
  sbatch_ = find_program("sbatch");
  squeue_ = find_program("squeue");
  scancel_ = find_program("scancel");
  scontrol_ = find_program("scontrol");
  if (sbatch_.empty() || squeue_.empty() || scancel_.empty() || scontrol_.empty())
    throw InvalidInput("slurm: sbatch, squeue, scancel and scontrol must be on PATH (Debian's slurm-client)");
  sinfo_ = find_program("sinfo");
  // Said at the start, not as each job's refusal by sbatch; a cluster that
  // does not answer now is asked again at the first launch.
  if (memory_mb > 0) {
    bool answered = false;
    if (const std::string why = memory_problem(memory_mb, &answered); !why.empty()) throw InvalidInput(why);
    if (answered) memory_checked_ = memory_mb;
  }
}

std::string SlurmExecutor::memory_problem(std::size_t memory_mb, bool* answered) const {
  *answered = false;
  if (sinfo_.empty()) return "";
  // One line per node and partition; the default partition ends in '*'.
  const ToolRun r = run_tool({sinfo_.string(), "--noheader", "--Node", "--format=%P|%m"}, kToolLimit);
  if (!r.ok()) return "";
  const std::vector<std::string> wanted =
      config_.partition.empty() ? std::vector<std::string>{} : split(config_.partition, ',');
  unsigned long long largest = 0;
  bool any = false;
  for (const std::string& line : split(r.output, '\n')) {
    const auto f = split(line, '|');
    if (f.size() < 2 || f[1].empty() || f[1].find_first_not_of("0123456789") != std::string::npos) continue;
    std::string partition = f[0];
    const bool default_partition = partition.ends_with('*');
    if (default_partition) partition.pop_back();
    if (wanted.empty() ? !default_partition : std::find(wanted.begin(), wanted.end(), partition) == wanted.end())
      continue;
    any = true;
    largest = std::max(largest, std::stoull(f[1].substr(0, 18)));
  }
  if (!any) return "";  // no such partition (sbatch says so), or no default one
  *answered = true;
  if (largest >= memory_mb) return "";
  const std::string where = config_.partition.empty() ? "" : " of partition " + config_.partition;
  return "no Slurm node" + where + " has the " + std::to_string(memory_mb) +
         " MB of memory a job asks (the largest has " + std::to_string(largest) +
         " MB): lower job_memory_mb (--job-memory-mb) to " + std::to_string(largest) +
         " or less, or name in slurm.partition a partition whose nodes have more";
}

std::string SlurmExecutor::unseen_data(const Tracked& t, const std::string& state, const std::string& said) const {
  // Only a launch that failed on the node it was given (Slurm 22.05:
  // FAILED, JobLaunchFailure); a node that died is NODE_FAIL, a job
  // cancelled while it waited never reached one.
  if (!config_.shared_data || state != "FAILED" || t.node.empty() || t.node == "(null)") return "";
  // On the node slurmstepd opens the job's --output and --error in the run's
  // directory before the batch script runs, and the script marks its start
  // there: none of them means the node did not see the directory.
  std::error_code ec;
  for (const char* file : {"stderr.txt", "batch-output.txt"})
    if (fs::exists(t.spec.dir / file, ec)) return "";
  if (!newest_run_file(t.spec.dir, "started").empty()) return "";
  return "the Slurm nodes cannot see the data directory " + t.spec.data_dir.string() +
         " that slurm.shared_data says they share (node " + t.node + " wrote nothing in the job's directory there; " +
         said +
         "): mount it at the same path on every node, or set slurm.shared_data to false (the nodes then fetch the "
         "inputs from slurm.server_url)";
}

Executor::Capabilities SlurmExecutor::capabilities() const {
  return {.requeue_lost = config_.requeue_lost,
          .remote_data = !config_.shared_data,
          .server_url = config_.server_url,
          .shared_data_setting = "slurm.shared_data"};
}

bool SlurmExecutor::sandboxed() const {
  return config_.sandbox && config_.shared_data && sandbox_ && sandbox_->enabled();
}

int SlurmExecutor::capacity() const {
  int running = 0;
  for (const auto& [id, t] : jobs_) running += t.running;
  return std::min(config_.max_jobs, running + config_.max_pending);
}

std::vector<std::string> SlurmExecutor::sbatch_command(const LaunchSpec& job) const {
  std::vector<std::string> a = {sbatch_.string(), "--parsable", "--job-name=" + job.name};
  // The batch script's environment is the short list a local worker gets
  // (child_process.h), not the server's.
  std::string exported;
  for (const std::string& v : job_environment()) exported += (exported.empty() ? "" : ",") + v.substr(0, v.find('='));
  a.push_back("--export=" + (exported.empty() ? std::string("NONE") : exported));
  if (job.token.empty()) {
    a.push_back("--chdir=" + job.dir.string());
    a.push_back("--output=" + (job.dir / "batch-output.txt").string());  // the script's; the worker's is stdout.N
    a.push_back("--error=" + (job.dir / "stderr.txt").string());
  } else {
    // The node sees nothing of the server's: the script keeps its own files
    // in a temporary directory of the node and sends back what matters.
    a.push_back("--chdir=/tmp");
    a.push_back("--output=/dev/null");
    a.push_back("--error=/dev/null");
  }
  a.push_back("--cpus-per-task=" + std::to_string(std::max(1, job.cpus)));
  // Slurm counts whole minutes; the executor's own watchdog holds the limit to the second.
  if (job.timeout_s > 0) a.push_back("--time=" + std::to_string(std::max(1L, long(std::ceil(job.timeout_s / 60)))));
  if (job.memory_mb > 0) a.push_back("--mem=" + std::to_string(job.memory_mb));
  if (!config_.partition.empty()) a.push_back("--partition=" + config_.partition);
  if (!config_.account.empty()) a.push_back("--account=" + config_.account);
  if (!config_.qos.empty()) a.push_back("--qos=" + config_.qos);
  for (const auto& extra : config_.sbatch_args) a.push_back(extra);
  a.push_back((job.dir / "slurm-job.sh").string());
  return a;
}

std::string SlurmExecutor::batch_script(const LaunchSpec& job, int slot) const {
  const std::string limit = job.memory_mb > 0 ? "ulimit -v " + std::to_string(job.memory_mb * 1024) + "; " : "";
  if (job.token.empty()) {
    // The worker under the job's address-space limit (as a local worker
    // runs), and its exit status kept beside its results: 128+N for a signal.
    // In the sandbox, the same bubblewrap command a local worker starts
    // with, under its process and file-size limits (prlimit: util-linux).
    // Outside the sandbox the script writes only in the run's directory,
    // which the job never sees: its stdout and exit status there, under the
    // run's number.  Each run (a requeued job's too) gets a fresh work/: an
    // earlier run's, links and all, is moved aside and removed, never
    // bound; an earlier run still going writes into the one it has.
    std::string command = quoted(worker_.string()) + " " + quoted((job.dir / "job.json").string());
    std::string give;
    if (sandboxed()) {
      const Sandbox::Command c = sandboxed_worker(*sandbox_, job, worker_, slot);
      // (Its process limit is set inside the sandbox where the server is not root: sandbox.h.)
      command = "prlimit" +
                (c.options.processes > 0 ? " --nproc=" + std::to_string(c.options.processes) : std::string()) +
                " --fsize=" + std::to_string(std::uint64_t(c.options.file_mb) << 20) + " --";
      for (const std::string& a : c.argv) command += " " + quoted(a);
      if (const auto uid = sandbox_->job_user(slot))
        give = "chown " + std::to_string(*uid) + ":" + std::to_string(*uid) + " work || exit 97\n";
    }
    return "#!/bin/sh\n# CGView job " + job.job_id + "\nexport PATH=/usr/local/bin:/usr/bin:/bin:$PATH\ncd " +
           quoted(job.dir.string()) +
           " || exit 97\n"
           "R=${SLURM_RESTART_COUNT:-0}\n"
           "case $R in *[!0-9]*|'') exit 97 ;; esac\n"
           "if [ -e work ] || [ -L work ]; then mv work \"old-work.$R.$$\" || exit 97; rm -rf \"old-work.$R.$$\"; fi\n"
           "mkdir -m 0700 work || exit 97\n"
           ": > \"started.$R\"\n" +
           give + "(" + limit + "exec " + command +
           ") > \"stdout.$R\"\nrc=$?\necho $rc > \"worker.exit.tmp.$R\" && mv \"worker.exit.tmp.$R\" "
           "\"worker.exit.$R\"\n"
           "exit $rc\n";
  }
  // No shared directory: curl fetches job.json and the inputs with the job's
  // own token, a loop sends the last progress line each second, and the
  // results, the worker's stderr and its exit status go back at the end
  // (result.json last of the results).
  std::string s = "#!/bin/sh\n# CGView job " + job.job_id +
                  "\nU=" + quoted(job.server_url + "/api/v1/worker/jobs/" + job.job_id) +
                  "\nW=$(mktemp -d \"${TMPDIR:-/tmp}/cgview-job.XXXXXX\") || exit 98\n"
                  "trap 'rm -rf \"$W\"' EXIT\n"
                  "cd \"$W\" || exit 98\n"
                  // The token reaches curl in a file only this user reads
                  // (printf is the shell's own: no command line holds it).
                  "umask 077\n"
                  "printf '%s\\n' " +
                  quoted("Authorization: Bearer " + job.token) +
                  " > \"$W/.auth\" || exit 98\n"
                  "H=\"@$W/.auth\"\n"
                  "get() { curl -fsS --retry 3 -H \"$H\" -o \"$2\" \"$U/$1\"; }\n"
                  "put() { curl -fsS --retry 3 -H \"$H\" -X PUT --data-binary \"@$1\" \"$U/files/$2\" >/dev/null; }\n"
                  "mkdir out || exit 98\n"
                  "get spec job.json || exit 98\n";
  for (const auto& [name, local] : job.remote_inputs) {
    const std::string parent = fs::path(local).parent_path().string();
    s += "mkdir -p " + quoted(parent) + " && get " + quoted("inputs/" + name) + " " + quoted(local) + " || exit 98\n";
  }
  s += "(" + limit + "exec " + quoted(worker_.string()) +
       " job.json) > stdout.txt 2> stderr.txt &\n"
       "pid=$!\n"
       "last=\n"
       "while kill -0 $pid 2>/dev/null; do\n"
       "  sleep 1\n"
       "  line=$(grep '^progress ' stdout.txt | tail -n 1)\n"
       "  if [ -n \"$line\" ] && [ \"$line\" != \"$last\" ]; then\n"
       "    printf '%s' \"$line\" | curl -fsS -H \"$H\" --data-binary @- \"$U/progress\" >/dev/null; last=$line\n"
       "  fi\n"
       "done\n"
       "wait $pid\n"
       "rc=$?\n"
       "for f in out/*; do\n"
       "  [ -f \"$f\" ] && [ \"${f##*/}\" != result.json ] && put \"$f\" \"${f##*/}\"\n"
       "done\n"
       "[ -f out/result.json ] && put out/result.json result.json\n"
       "put stderr.txt stderr.txt\n"
       "echo $rc > worker.exit && put worker.exit worker.exit\n"
       "exit $rc\n";
  return s;
}

std::string SlurmExecutor::launch(const LaunchSpec& job) {
  if (job.memory_mb > 0 && job.memory_mb != memory_checked_) {
    bool answered = false;
    if (const std::string why = memory_problem(job.memory_mb, &answered); !why.empty()) throw LaunchError(why);
    if (answered) memory_checked_ = job.memory_mb;
  }
  Sandbox::Slot slot;
  if (sandboxed()) slot = sandbox_->take_slot();
  std::string script;
  try {
    script = batch_script(job, slot.number());
  } catch (const std::exception& e) {
    throw LaunchError(e.what());
  }
  try {
    write_file_bytes(job.dir / "slurm-job.sh", script);
  } catch (const std::exception& e) {
    throw LaunchError(std::string("the job's batch script could not be written: ") + e.what());
  }
  const ToolRun r = run_tool(sbatch_command(job), kToolLimit);
  const std::string id = first_line(r.output).substr(0, first_line(r.output).find(';'));
  if (!r.ok() || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    std::string why = r.output;
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    throw LaunchError("the cluster refused the job (sbatch: " + (why.empty() ? std::string("no answer") : why) + ")");
  }
  Tracked& t = jobs_[job.job_id];
  t.spec = job;
  t.slurm_id = id;
  t.slot = std::move(slot);
  return id;
}

bool SlurmExecutor::adopt(const LaunchSpec& job, const std::string& handle) {
  if (handle.empty() || handle.find_first_not_of("0123456789") != std::string::npos) return false;
  Tracked& t = jobs_[job.job_id];
  t.spec = job;
  t.slurm_id = handle;
  return true;
}

void SlurmExecutor::read_progress(Tracked& t, std::vector<ExecutorEvent>& events) {
  const std::string name = newest_run_file(t.spec.dir, "stdout");
  if (name.empty()) return;
  // Requeued: the new run's output begins again.
  if (name != t.output_file) t.output_file = name, t.output_read = 0, t.output.clear();
  std::uint64_t size = 0;
  const auto more = JobDir(t.spec.dir).read_from(name, t.output_read, 1 << 20, &size);
  if (!more || more->empty()) return;
  t.output_read += more->size();
  t.output += *more;
  ExecutorEvent e;
  e.job_id = t.spec.job_id;
  e.kind = ExecutorEvent::Kind::progress;
  if (!t.garbage.empty()) return;
  const ProgressRead read = read_progress_lines(t.output, e.progress, e.stage);
  if (!read.garbage.empty() && !t.cancelling) {
    t.garbage = read.garbage;
    t.cancelling = true;
    run_tool({scancel_.string(), t.slurm_id}, kToolLimit);
  } else if (read.found && !t.cancelling) {
    events.push_back(std::move(e));
  }
}

WorkerEnd SlurmExecutor::ended(const Tracked& t, const std::string& state, const std::string& reason) const {
  WorkerEnd end;
  const std::string said = "Slurm job " + t.slurm_id + " " + (state.empty() ? "unknown" : state) +
                           (reason.empty() || reason == "None" ? "" : ", " + reason);
  end.detail = said;
  if (!t.garbage.empty()) {
    end.how = WorkerEnd::How::garbled;
    end.detail = t.garbage;
    return end;
  }
  if (t.timed_out || state == "TIMEOUT") {
    end.how = WorkerEnd::How::timed_out;
    return end;
  }
  // slurmstepd says so in the job's stderr when it kills for memory (OverMemoryKill, or cgroups' oom).
  const JobDir run(t.spec.dir);
  std::string why;
  const std::string err = run.read("stderr.txt", kMaxReportBytes, &why, true).value_or("");
  if (state == "OUT_OF_MEMORY" || err.find("exceeded memory limit") != std::string::npos ||
      err.find("oom_kill event") != std::string::npos || err.find("oom-kill event") != std::string::npos) {
    end.how = WorkerEnd::How::out_of_memory;
    return end;
  }
  // The worker's own exit status, as its batch script saw it.
  const std::string exit_file = newest_exit_file(t.spec.dir);
  const std::string code =
      exit_file.empty() ? "" : first_line(run.read(exit_file, kMaxReportBytes, &why, true).value_or(""));
  if (!code.empty() && code.find_first_not_of("0123456789") == std::string::npos && code.size() < 5) {
    const int c = std::stoi(code);
    if (c > 128 && c < 128 + 65) end.how = WorkerEnd::How::signaled, end.signal = c - 128;
    else end.how = WorkerEnd::How::exited, end.code = c;
    return end;
  }
  if (std::string why = unseen_data(t, state, said); !why.empty()) {
    end.how = WorkerEnd::How::not_started;
    end.detail = std::move(why);
    return end;
  }
  if (state == "NODE_FAIL" || state == "BOOT_FAIL") {
    end.how = WorkerEnd::How::node_failed;
    return end;
  }
  end.how = WorkerEnd::How::lost;
  if (state == "CANCELLED") end.detail = "cancelled in the cluster, not by CGView (" + said + ")";
  else if (state == "PREEMPTED") end.detail = "preempted by the cluster (" + said + ")";
  else if (state == "DEADLINE") end.detail = "the cluster's deadline passed (" + said + ")";
  else if (state.empty()) end.detail = "Slurm no longer knows job " + t.slurm_id + " (purged, or lost with its node)";
  else end.detail = "the worker did not run to its end (" + said + ")";
  return end;
}

bool SlurmExecutor::held_with_a_result(Tracked& t, Clock::time_point now) const {
  if (newest_exit_file(t.spec.dir).empty()) {
    t.held_since.reset();
    return false;
  }
  if (!t.held_since) t.held_since = now;
  return now - *t.held_since > kHeldWithAResult;
}

void SlurmExecutor::refresh(std::vector<ExecutorEvent>& events) {
  ++squeue_calls_;
  // Every job of this user the controller still holds, ended ones included
  // (for MinJobAge after their end): one call however many are in flight.
  const ToolRun r =
      run_tool({squeue_.string(), "--noheader", "--me", "--states=all", "--format=%i|%T|%r|%N"}, kToolLimit);
  if (!r.ok()) return;                                   // the controller is away: try again next cycle, change nothing
  std::map<std::string, std::vector<std::string>> rows;  // Slurm id -> state, reason, nodes
  for (const std::string& line : split(r.output, '\n')) {
    auto f = split(line, '|');
    if (f.size() >= 4) rows[f[0]] = {f[1], f[2], f[3]};
  }
  const auto now = Clock::now();
  for (auto it = jobs_.begin(); it != jobs_.end();) {
    Tracked& t = it->second;
    ExecutorEvent e;
    e.job_id = it->first;
    const auto row = rows.find(t.slurm_id);
    std::string state, reason, node;
    if (row != rows.end()) {
      state = row->second[0], reason = row->second[1], node = row->second[2];
      if (!node.empty()) t.node = node;
      t.unseen = 0;
    } else if (++t.unseen < 2) {
      ++it;  // just submitted, or a hiccup: look again next cycle
      continue;
    } else {
      // Gone from squeue: scontrol may still hold it, else it is forgotten.
      const ToolRun s = run_tool({scontrol_.string(), "show", "job", "-o", t.slurm_id}, kToolLimit);
      if (s.ok()) state = field(s.output, "JobState"), reason = field(s.output, "Reason");
      if (!state.empty() && !final_state(state)) {
        ++it;
        continue;
      }
    }
    const bool active_state = state == "RUNNING" || state == "COMPLETING";
    // Its newest run ended with its result on disk, yet the cluster holds
    // the job (a launch it thought failed while munged was away: "launch
    // failed requeued held"): settled from that result, not left waiting.
    // A job merely requeued (its node failed) runs again as the cluster wants.
    const bool held = state == "REQUEUE_HOLD" || state == "SPECIAL_EXIT" || reason.starts_with("JobHeld") ||
                      reason.find("held") != std::string::npos;
    const bool held_done = held && !t.cancelling && held_with_a_result(t, now);
    if (held_done) run_tool({scancel_.string(), t.slurm_id}, kToolLimit);
    if (state.empty() || final_state(state) || held_done) {
      read_progress(t, events);
      e.kind = ExecutorEvent::Kind::ended;
      e.end = ended(t, state, reason);
      events.push_back(std::move(e));
      unwatch(it->first);
      it = jobs_.erase(it);
      continue;
    }
    if (active_state) {
      if (!t.running) {
        t.running = true;
        // Slurm's --time is in minutes: the job's own limit is held by the
        // watchdog (poll), from each start (a requeued job's again).
        watch(it->first, t.spec.timeout_s);
        e.kind = ExecutorEvent::Kind::started;
        e.node = node;
        events.push_back(e);
      }
    } else if (!t.cancelling) {  // PENDING, REQUEUED, SUSPENDED, ...: waiting, and why
      const std::string why =
          state == "PENDING" ? (reason == "None" ? "" : reason) : state + (reason == "None" ? "" : ": " + reason);
      if (t.running || why != t.reason) {
        if (t.running) unwatch(it->first);
        t.running = false;
        t.reason = why;
        e.kind = ExecutorEvent::Kind::waiting;
        e.reason = why;
        events.push_back(e);
      }
    }
    ++it;
  }
}

std::vector<ExecutorEvent> SlurmExecutor::poll(std::chrono::milliseconds timeout) {
  std::vector<ExecutorEvent> events;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(config_.poll_s));
  const auto due = last_refresh_ + period;
  const auto now = Clock::now();
  if (jobs_.empty() || due > now) {
    const auto wait = jobs_.empty() ? timeout
                                    : std::min<std::chrono::milliseconds>(
                                          timeout, std::chrono::duration_cast<std::chrono::milliseconds>(due - now) +
                                                       std::chrono::milliseconds(1));
    pollfd p{wake_fd(), POLLIN, 0};
    ::poll(&p, 1, int(wait.count()));
    drain_wake();
  }
  // What was cancelled, and what ran over its time: one scancel.
  std::vector<std::string> scancel = {scancel_.string()};
  for (const auto& id : take_cancels())
    if (const auto it = jobs_.find(id); it != jobs_.end() && !it->second.cancelling) {
      it->second.cancelling = true;
      scancel.push_back(it->second.slurm_id);
    }
  for (const auto& id : overdue())
    if (const auto it = jobs_.find(id); it != jobs_.end() && it->second.running && !it->second.cancelling) {
      it->second.timed_out = it->second.cancelling = true;
      scancel.push_back(it->second.slurm_id);
    }
  if (scancel.size() > 1) run_tool(scancel, kToolLimit);
  for (auto& [id, t] : jobs_)
    if (t.running) read_progress(t, events);
  if (Clock::now() >= last_refresh_ + period && !jobs_.empty()) {
    last_refresh_ = Clock::now();
    refresh(events);
  }
  return events;
}

}  // namespace cgview::server
