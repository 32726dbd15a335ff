// Jobs through the local executor and through a three-node Slurm cluster
// on this same machine (tests/slurm's harness), in one run: 200 jobs (150
// tiny centroid_distance, 50 sdf on elephant.off, each with other
// parameters so that the cache never answers) submitted at once; then 10
// tiny jobs one at a time (the per-job overhead); then 1,000 jobs that wait
// (Slurm: submitted held; local: behind two long jobs) while the server's
// CPU is measured for 30 s.  The cluster's 6 CPUs are this machine's cores,
// oversubscribed: the comparison is of overhead, not of capacity.
//
//   build/bin/slurm_bench [--jobs 200] [--waiting 1000] [--idle-s 30]
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "server_harness.h"
#include "slurm_cluster.h"
#include "test_support.h"

using namespace cgview::test;
using nlohmann::json;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p / 100.0 * double(v.size())))];
}

// CPU seconds of a process (user + system), and of its waited-for children.
double cpu_s(pid_t pid, bool children) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string s((std::istreambuf_iterator<char>(f)), {});
  const auto close = s.rfind(')');
  if (close == std::string::npos) return -1;
  std::istringstream in(s.substr(close + 2));
  std::vector<std::string> fields;
  for (std::string x; in >> x;) fields.push_back(x);
  // Fields from 3 (state): utime is 14, stime 15, cutime 16, cstime 17.
  const double tick = double(::sysconf(_SC_CLK_TCK));
  double t = (std::stod(fields[11]) + std::stod(fields[12])) / tick;
  if (children) t += (std::stod(fields[13]) + std::stod(fields[14])) / tick;
  return t;
}

struct Run {
  std::string executor;
  double submit_s = 0, makespan_s = 0, throughput = 0, p50 = 0, p99 = 0, tiny_p50 = 0, sdf_p50 = 0;
  double lone_mean = 0, lone_p50 = 0;
  double handover_s = 0;  // until every waiting job was with Slurm
  double idle_cpu_per_min = 0, idle_cpu_children_per_min = 0, idle_ctld_per_min = 0;
  int failed = 0;
};

std::string upload(unsigned short port, const std::string& name) {
  const auto r = http_call(port, Method::post, "/api/v1/meshes?name=" + name, read_bytes(sample(name)));
  if (r.status != 201)
    throw std::runtime_error("upload failed: " + std::to_string(r.status) + " " + r.ec.message() + " " + r.body);
  return r.body_json()["id"];
}

std::string submit(unsigned short port, const json& body) {
  const auto r = http_call(port, Method::post, "/api/v1/jobs", body.dump());
  if (r.status != 201)
    throw std::runtime_error("submit failed: " + std::to_string(r.status) + " " + r.ec.message() + " " + r.body);
  return r.body_json()["id"];
}

// Polls GET /api/v1/jobs until each id ended; the time each was seen ended.
std::map<std::string, Clock::time_point> wait_all(unsigned short port, const std::vector<std::string>& ids,
                                                  int& failed) {
  std::map<std::string, Clock::time_point> ended;
  const std::set<std::string> wanted(ids.begin(), ids.end());
  const auto deadline = Clock::now() + std::chrono::minutes(20);
  while (ended.size() < ids.size() && Clock::now() < deadline) {
    const json list = http_get(port, "/api/v1/jobs").body_json();
    const auto now = Clock::now();
    for (const auto& j : list.value("jobs", json::array())) {
      const std::string id = j.value("id", ""), s = j.value("state", "");
      if ((s == "done" || s == "failed" || s == "cancelled") && wanted.count(id) && !ended.count(id)) {
        ended[id] = now;
        if (s != "done") ++failed;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return ended;
}

Run run(const std::string& executor, const fs::path& dir, SlurmCluster* cluster, int jobs, int waiting, int idle_s) {
  Run out;
  out.executor = executor;
  ServerProcess server;
  std::vector<std::string> args = {"--worker", bin("cgview-worker"), "--job-workers", "2", "--job-memory-mb", "2048"};
  if (executor == "slurm") {
    write_text(dir / "config.json", json{{"slurm", {{"poll_s", 0.2}, {"max_jobs", 2000}}}}.dump());
    args.insert(args.end(), {"--executor", "slurm", "--config", (dir / "config.json").string()});
  }
  fs::create_directories(dir / ("log-" + executor));
  if (!server.start(dir / ("data-" + executor), args, dir / ("log-" + executor)))
    throw std::runtime_error("the server did not start");
  const unsigned short port = server.port();
  const std::string sphere = upload(port, "sphere.off"), elephant = upload(port, "elephant.off");

  // The burst.
  std::vector<std::string> ids;
  std::map<std::string, Clock::time_point> submitted;
  std::map<std::string, bool> is_sdf;
  const auto t0 = Clock::now();
  for (int i = 0; i < jobs; ++i) {
    const bool sdf = i % 4 == 3;  // 50 of 200
    const json body =
        sdf ? json{{"algorithm", "sdf"}, {"inputs", {{"mesh", elephant}}}, {"params", {{"rays", 10 + i % 200}}}}
            : json{{"algorithm", "centroid_distance"},
                   {"inputs", {{"mesh", sphere}}},
                   {"params", {{"exponent", 0.1 + 0.001 * i}}}};
    const auto at = Clock::now();
    const std::string id = submit(port, body);
    ids.push_back(id);
    submitted[id] = at;
    is_sdf[id] = sdf;
  }
  out.submit_s = ms(Clock::now() - t0) / 1000;
  const auto ended = wait_all(port, ids, out.failed);
  std::vector<double> all, tiny, sdf;
  Clock::time_point last = t0;
  for (const auto& id : ids) {
    if (!ended.count(id)) continue;
    const double d = ms(ended.at(id) - submitted[id]);
    all.push_back(d);
    (is_sdf[id] ? sdf : tiny).push_back(d);
    last = std::max(last, ended.at(id));
  }
  out.makespan_s = ms(last - t0) / 1000;
  out.throughput = double(all.size()) / out.makespan_s;
  out.p50 = percentile(all, 50), out.p99 = percentile(all, 99);
  out.tiny_p50 = percentile(tiny, 50), out.sdf_p50 = percentile(sdf, 50);

  // Lone jobs: one at a time.
  std::vector<double> lone;
  for (int i = 0; i < 10; ++i) {
    const auto at = Clock::now();
    const std::string id = submit(port, json{{"algorithm", "centroid_distance"},
                                             {"inputs", {{"mesh", sphere}}},
                                             {"params", {{"exponent", 3.0 + 0.01 * i}}}});
    int f = 0;
    const auto e = wait_all(port, {id}, f);
    if (e.count(id)) lone.push_back(ms(e.at(id) - at));
  }
  double sum = 0;
  for (double d : lone) sum += d;
  out.lone_mean = lone.empty() ? 0 : sum / double(lone.size());
  out.lone_p50 = percentile(lone, 50);
  server.kill_now();

  // Waiting jobs: the server's cost of holding them.  Long sleeps of the
  // test worker: locally two run and the rest wait in the fair queue; on
  // Slurm they are submitted held and wait in the cluster's queue.
  if (waiting > 0) {
    std::vector<std::string> more = args;
    more[1] = bin("cgview-worker-test");
    if (executor == "slurm") {
      write_text(dir / "config.json", json{{"slurm",
                                            {{"poll_s", 1.0},
                                             {"max_jobs", waiting + 10},
                                             {"max_pending", waiting + 10},
                                             {"sbatch_args", {"--hold"}}}}}
                                          .dump());
    }
    ServerProcess idle;
    fs::create_directories(dir / ("log-idle-" + executor));
    if (!idle.start(dir / ("idle-" + executor), more, dir / ("log-idle-" + executor)))
      throw std::runtime_error("the server did not start");
    const std::string m = upload(idle.port(), "sphere.off");
    for (int i = 0; i < waiting; ++i)
      submit(idle.port(),
             json{{"algorithm", "test_sleep"}, {"inputs", {{"mesh", m}}}, {"params", {{"seconds", 600 + 0.001 * i}}}});
    // Until every job is with Slurm (held), or queued locally.
    const auto handing = Clock::now();
    if (cluster) {
      const auto deadline = Clock::now() + std::chrono::minutes(5);
      while (Clock::now() < deadline &&
             std::stoi("0" + cluster->run("squeue --noheader --me --states=PENDING | wc -l")) < waiting)
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
      out.handover_s = ms(Clock::now() - handing) / 1000;
    }
    std::this_thread::sleep_for(std::chrono::seconds(2));
    const double c0 = cpu_s(idle.pid(), false), cc0 = cpu_s(idle.pid(), true) - c0;
    const double k0 = cluster ? cpu_s(cluster->ctld_pid(), false) : 0;
    std::this_thread::sleep_for(std::chrono::seconds(idle_s));
    const double c1 = cpu_s(idle.pid(), false), cc1 = cpu_s(idle.pid(), true) - c1;
    const double k1 = cluster ? cpu_s(cluster->ctld_pid(), false) : 0;
    out.idle_cpu_per_min = (c1 - c0) * 60 / idle_s;
    out.idle_cpu_children_per_min = (cc1 - cc0) * 60 / idle_s;
    out.idle_ctld_per_min = (k1 - k0) * 60 / idle_s;
    idle.kill_now();
    if (cluster) cluster->run("scancel --me");
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int jobs = 200, waiting = 1000, idle_s = 30;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--jobs") jobs = std::stoi(argv[i + 1]);
    else if (a == "--waiting") waiting = std::stoi(argv[i + 1]);
    else if (a == "--idle-s") idle_s = std::stoi(argv[i + 1]);
  }
  std::string why;
  if (!SlurmCluster::available(&why)) {
    std::fprintf(stderr, "slurm_bench: %s\n", why.c_str());
    return 1;
  }
  const fs::path dir = temp_dir("slurm-bench");
  SlurmCluster cluster;
  cluster.set_conf("MaxJobCount", "20000");
  if (!cluster.start(dir / "c", 3, &why)) {
    std::fprintf(stderr, "slurm_bench: the cluster did not start: %s\n", why.c_str());
    return 1;
  }
  ::setenv("SLURM_CONF", cluster.conf().c_str(), 1);
  std::vector<Run> runs;
  for (const std::string e : {"local", "slurm"}) {
    std::fprintf(stderr, "slurm_bench: %s executor...\n", e.c_str());
    runs.push_back(run(e, dir, e == "slurm" ? &cluster : nullptr, jobs, waiting, idle_s));
  }
  cluster.stop();
  std::printf(
      "%d jobs (%d tiny centroid_distance on sphere.off, %d sdf on elephant.off), 2 local workers, 3 Slurm nodes of 2 "
      "CPUs on %u cores\n\n",
      jobs, jobs - jobs / 4, jobs / 4, std::thread::hardware_concurrency());
  std::printf("| measure | local | slurm | slurm / local |\n|---|---:|---:|---:|\n");
  auto row = [&](const char* name, double Run::*f, const char* fmt) {
    char a[32], b[32];
    std::snprintf(a, sizeof a, fmt, runs[0].*f);
    std::snprintf(b, sizeof b, fmt, runs[1].*f);
    std::printf("| %s | %s | %s | %.2f |\n", name, a, b, runs[0].*f > 0 ? runs[1].*f / (runs[0].*f) : 0.0);
  };
  row("burst: submitted in (s)", &Run::submit_s, "%.2f");
  row("burst: first submit to last done (s)", &Run::makespan_s, "%.2f");
  row("throughput (jobs/s)", &Run::throughput, "%.1f");
  row("submit->done p50 (ms)", &Run::p50, "%.0f");
  row("submit->done p99 (ms)", &Run::p99, "%.0f");
  row("tiny job p50 (ms)", &Run::tiny_p50, "%.0f");
  row("sdf job p50 (ms)", &Run::sdf_p50, "%.0f");
  row("lone tiny job, mean (ms): the per-job overhead", &Run::lone_mean, "%.1f");
  row("lone tiny job, p50 (ms)", &Run::lone_p50, "%.1f");
  std::printf("| failed jobs | %d | %d | |\n", runs[0].failed, runs[1].failed);
  std::printf("\n%d jobs waiting (Slurm: held in the cluster's queue; local: in the fair queue), %d s:\n\n", waiting,
              idle_s);
  std::printf("| CPU seconds per minute | local | slurm |\n|---|---:|---:|\n");
  std::printf("| the server | %.3f | %.3f |\n", runs[0].idle_cpu_per_min, runs[1].idle_cpu_per_min);
  std::printf("| its children (squeue, sbatch) | %.3f | %.3f |\n", runs[0].idle_cpu_children_per_min,
              runs[1].idle_cpu_children_per_min);
  std::printf("| slurmctld | - | %.3f |\n", runs[1].idle_ctld_per_min);
  std::printf("\nHanding the %d jobs to Slurm (sbatch each, %d a scheduler turn) took %.1f s after the last submit.\n",
              waiting, 32, runs[1].handover_s);
  return 0;
}
