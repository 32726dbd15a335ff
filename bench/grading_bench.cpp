// A deadline's rush on the real server, in its sandbox: a class of students
// (enrolled by roster, signed in by their links) submitting right, wrong,
// crashing, looping and non-compiling plugins to an assignment graded on
// hidden meshes of up to 50k faces.  It prints submission-to-score p50 and
// p95 by kind, whether every submission was graded, and the first
// submissions of the other students beside the twenty of one student sent
// in a burst at the start (fairness).  Side by side in the same run, the
// reference: one right solution built and run on the hidden meshes by hand,
// as ordinary plugin jobs one after another, with nothing else queued; the
// ratio says what grading under the rush costs over that.
//
//   build/bin/grading_bench [--submissions 200] [--students 60] [--window-s 300]
//                           [--time-limit-s 5] [--workers 2] [--server build/bin/cgview-server]
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_server.h"
#include "centroid_distance_plugin.h"

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;
using cgview::bench::add_teacher;
using cgview::bench::call;
using cgview::bench::percentile;
using cgview::bench::request;

namespace {

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string read_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

const std::string kDistance = "field.values[i] = float(std::pow(norm(mesh.positions[i] - c), p.exponent));";

// A student's file of a kind; `n` makes each text its own (students' files differ: each is built).
std::string source_of(const std::string& kind, int n) {
  std::string s = cgview::test::centroid_distance_plugin(CGVIEW_SOURCE_DIR, "distance");
  auto replace = [&](const std::string& to) { s.replace(s.find(kDistance), kDistance.size(), to); };
  if (kind == "wrong") replace(kDistance.substr(0, kDistance.size() - 2) + " * 1.2f);");
  else if (kind == "crash") replace("*(volatile int*)nullptr = 1;");
  else if (kind == "loop") replace("for (volatile int spin = 0;; spin = spin + 1) {}");
  else if (kind == "broken") replace("not C++ at all");
  return s + "// student file " + std::to_string(n) + "\n";
}

}  // namespace

// The whole run; main catches what it throws, so that the server is stopped
// (ServerProcess's destructor) rather than left running by std::terminate.
int run(int argc, char** argv) {
  int submissions = 200, students = 60, workers = 2;
  double window_s = 300, time_limit = 60;
  std::string server = std::string(CGVIEW_BIN_DIR) + "/cgview-server";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--submissions") submissions = std::stoi(v);
    else if (a == "--students") students = std::stoi(v);
    else if (a == "--window-s") window_s = std::stod(v);
    else if (a == "--time-limit-s") time_limit = std::stod(v);
    else if (a == "--workers") workers = std::stoi(v);
    else if (a == "--server") server = v;
  }
  const fs::path data = fs::temp_directory_path() / ("cgview-grading-bench-" + std::to_string(::getpid()));
  fs::remove_all(data);
  const std::string tina = add_teacher(server, data);
  cgview::bench::ServerProcess srv(
      server, data, {"--auth", "required", "--job-workers", std::to_string(workers), "--job-memory-mb", "2048"});
  const unsigned short port = srv.port;

  // The class: a roster, each student signed in by their link.
  const json course = request(port, "POST", "/api/v1/courses", {{"title", "Rush"}}, tina);
  json roster = json::array();
  for (int s = 0; s < students; ++s) roster.push_back("s" + std::to_string(s));
  const json enrolled =
      request(port, "POST", "/api/v1/courses/" + course["id"].get<std::string>() + "/members", roster, tina);
  std::vector<std::string> tokens;
  for (const json& link : enrolled["links"])
    tokens.push_back(request(port, "POST", "/api/v1/tickets/redeem", {{"ticket", link["ticket"]}}, "")["token"]);

  // Three hidden meshes of up to 50k faces, the reference built.
  std::vector<std::string> hidden;
  for (const char* name : {"armadillo.off", "diplodocus.off", "man.off"})
    hidden.push_back(cgview::bench::upload(port, name, read_file(fs::path(CGVIEW_SAMPLES_DIR) / name), tina));
  const json plugin =
      request(port, "POST", "/api/v1/plugins", {{"name", "reference"}, {"source", source_of("right", -1)}}, tina);
  const std::string plugin_id = plugin["id"];
  json build = request(port, "POST", "/api/v1/plugins/" + plugin_id + "/build", nullptr, tina);
  while (build.value("state", "") == "queued" || build.value("state", "") == "running") {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    build = request(port, "GET", "/api/v1/jobs/" + build["id"].get<std::string>(), nullptr, tina);
  }

  // The reference side: one right file built and run on each hidden mesh by hand, nothing else queued.
  const auto by_hand0 = Clock::now();
  {
    const json p =
        request(port, "POST", "/api/v1/plugins", {{"name", "byhand"}, {"source", source_of("right", -2)}}, tina);
    json b = request(port, "POST", "/api/v1/plugins/" + p["id"].get<std::string>() + "/build", nullptr, tina);
    for (const std::string& id : {b["id"].get<std::string>()}) {
      for (json j = b; j.value("state", "") == "queued" || j.value("state", "") == "running";) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        j = request(port, "GET", "/api/v1/jobs/" + id, nullptr, tina);
      }
    }
    for (const std::string& m : hidden) {
      json j = request(port, "POST", "/api/v1/jobs",
                       {{"algorithm", "distance"}, {"plugin", p["id"]}, {"inputs", {{"mesh", m}}}}, tina);
      while (j.value("state", "") == "queued" || j.value("state", "") == "running") {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        j = request(port, "GET", "/api/v1/jobs/" + j["id"].get<std::string>(), nullptr, tina);
      }
    }
  }
  const double by_hand = since(by_hand0);

  const json assignment = request(port, "POST", "/api/v1/courses/" + course["id"].get<std::string>() + "/assignments",
                                  {{"title", "Distances"},
                                   {"hidden_meshes", hidden},
                                   {"reference_plugin", plugin_id},
                                   {"time_limit_s", time_limit},
                                   {"points_per_mesh", 1}},
                                  tina);
  const std::string aid = assignment["id"];

  // The plan: student 0 sends twenty at once at the start; the others arrive
  // at random through the window (a fixed seed: every run the same plan).
  struct Planned {
    double at;
    int student;
    std::string kind;
  };
  std::vector<Planned> plan;
  std::mt19937 rng(7);
  const std::vector<std::string> kinds = {"right", "right", "right", "right", "right",
                                          "wrong", "wrong", "crash", "loop",  "broken"};
  const int burst = std::min(20, submissions);
  for (int i = 0; i < burst; ++i) plan.push_back({0, 0, kinds[std::size_t(i) % kinds.size()]});
  std::uniform_real_distribution<double> when(0, window_s);
  for (int i = burst; i < submissions; ++i)
    plan.push_back({when(rng), 1 + (i % std::max(1, students - 1)), kinds[rng() % kinds.size()]});
  std::stable_sort(plan.begin(), plan.end(), [](const Planned& a, const Planned& b) { return a.at < b.at; });

  struct Sent {
    std::string id, kind;
    int student;
    double sent_at, scored_at = -1;
    std::string state;
  };
  std::vector<Sent> sent;
  std::map<std::string, std::size_t> by_id;
  const auto t0 = Clock::now();
  std::size_t next = 0;
  auto poll = [&] {
    const json all = request(port, "GET", "/api/v1/assignments/" + aid + "/submissions", nullptr, tina);
    const double now = since(t0);
    for (const json& s : all) {
      const auto it = by_id.find(s.value("id", ""));
      if (it == by_id.end()) continue;
      Sent& x = sent[it->second];
      if (x.scored_at < 0 && (s["state"] == "graded" || s["state"] == "failed")) {
        x.scored_at = now;
        x.state = s["state"];
      }
    }
  };
  for (;;) {
    while (next < plan.size() && plan[next].at <= since(t0)) {
      const Planned& p = plan[next++];
      const double at = since(t0);
      const json s = request(port, "POST", "/api/v1/assignments/" + aid + "/submissions",
                             {{"source", source_of(p.kind, int(next))}}, tokens.at(std::size_t(p.student)));
      by_id[s["id"]] = sent.size();
      sent.push_back({s["id"], p.kind, p.student, at, -1, ""});
    }
    poll();
    const bool all_scored =
        next == plan.size() && std::all_of(sent.begin(), sent.end(), [](const Sent& s) { return s.scored_at >= 0; });
    if (all_scored || since(t0) > window_s + 1800) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }

  // Where the workers' time went: each run's own time (run_s), by kind, and
  // each hidden mesh's limit (ten times the reference's run there).
  // (At the token's rate limit of 50 requests a second.)
  const auto job_of = [&](const std::string& id) {
    std::this_thread::sleep_for(std::chrono::milliseconds(21));
    return request(port, "GET", "/api/v1/jobs/" + id, nullptr, tina);
  };
  std::map<std::string, double> run_seconds;
  std::map<std::string, std::string> kind_of;
  for (const Sent& s : sent) kind_of[s.id] = s.kind;
  for (const json& s : request(port, "GET", "/api/v1/assignments/" + aid + "/submissions", nullptr, tina))
    for (const json& r : s.value("results", json::array()))
      if (!r.value("job", "").empty()) run_seconds[kind_of[s.value("id", "")]] += job_of(r["job"]).value("run_s", 0.0);
  std::string limits;
  for (const json& ref :
       request(port, "GET", "/api/v1/assignments/" + aid, nullptr, tina).value("reference_jobs", json::array())) {
    const double r = job_of(ref).value("run_s", 0.0);
    char one[64];
    std::snprintf(one, sizeof one, "%s%.2f s (limit %.1f s)", limits.empty() ? "" : ", ", r,
                  std::min(time_limit, std::max(1.0, 10 * r)));
    limits += one;
  }

  std::map<std::string, std::vector<double>> latency;
  std::vector<double> all, burst_student, others_first;
  std::map<int, bool> seen_first;
  std::size_t lost = 0;
  for (const Sent& s : sent) {
    if (s.scored_at < 0) {
      ++lost;
      continue;
    }
    const double d = s.scored_at - s.sent_at;
    latency[s.kind].push_back(d);
    all.push_back(d);
    if (s.student == 0) burst_student.push_back(d);
    else if (!seen_first[s.student]) {
      seen_first[s.student] = true;
      if (s.sent_at < 60) others_first.push_back(d);  // those that met the burst
    }
  }
  std::printf(
      "grading_bench: %d submissions from %d students over %.0f s, 3 hidden meshes (52k, 48k, 35k faces), "
      "%d workers, time limit %.0f s\n",
      submissions, students, window_s, workers, time_limit);
  std::printf("%-8s %6s %8s %8s\n", "kind", "count", "p50 s", "p95 s");
  for (const auto& [kind, v] : latency)
    std::printf("%-8s %6zu %8.2f %8.2f\n", kind.c_str(), v.size(), percentile(v, 0.5), percentile(v, 0.95));
  std::printf("%-8s %6zu %8.2f %8.2f\n", "all", all.size(), percentile(all, 0.5), percentile(all, 0.95));
  std::printf("not scored: %zu of %zu\n", lost, sent.size());
  std::printf("the reference's runs on the hidden meshes: %s\n", limits.c_str());
  std::printf("worker-seconds in the submissions' runs (not their builds):");
  for (const auto& [kind, t] : run_seconds) std::printf(" %s %.0f", kind.c_str(), t);
  std::printf("\n");
  std::printf(
      "student 0's burst of %zu: p50 %.2f s; other students' first submissions in the first minute (%zu): "
      "p50 %.2f s, p95 %.2f s\n",
      burst_student.size(), percentile(burst_student, 0.5), others_first.size(), percentile(others_first, 0.5),
      percentile(others_first, 0.95));
  std::printf(
      "reference: one right file built and run on the 3 meshes by hand, nothing queued: %.2f s; "
      "right submissions' p50 under the rush / that: %.2fx\n",
      by_hand, by_hand > 0 ? percentile(latency["right"], 0.5) / by_hand : 0.0);
  std::printf("server peak RSS %.0f MB\n", double(srv.peak_rss_kb()) / 1024);
  fs::remove_all(data);
  return lost == 0 ? 0 : 1;
}

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grading_bench: %s\n", e.what());
    return 1;
  }
}
