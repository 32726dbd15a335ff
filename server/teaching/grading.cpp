#include "teaching/grading.h"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "compare/compare_output.h"
#include "core/errors.h"
#include "io/parse_json.h"
#include "jobs/scheduler.h"
#include "mesh_service.h"
#include "plugin_service.h"
#include "sqlite_stmt.h"
#include "teaching/courses.h"

namespace cgview::server {

using nlohmann::json;

namespace {

constexpr std::size_t kMaxStatement = 64 * 1024, kMaxStarter = 256 * 1024, kMaxHidden = 20, kMaxPublic = 50;
constexpr double kDefaultTimeLimit = 60;

OutputKind kind_named(const std::string& name) {
  for (OutputKind k : kOutputKinds)
    if (name == to_string(k)) return k;
  throw InvalidInput("an output of kind '" + name + "' cannot be compared");
}

// "2026-12-01T23:59:00Z", as now_iso8601() writes it, so that times compare as text.
bool iso_time(const std::string& t) {
  if (t.size() != 20 || t[4] != '-' || t[7] != '-' || t[10] != 'T' || t[13] != ':' || t[16] != ':' || t[19] != 'Z')
    return false;
  for (std::size_t i : {0, 1, 2, 3, 5, 6, 8, 9, 11, 12, 14, 15, 17, 18})
    if (!std::isdigit(static_cast<unsigned char>(t[i]))) return false;
  return true;
}

std::vector<std::string> id_list(const json& body, const char* key, std::size_t max, bool required) {
  const json v = body.value(key, json::array());
  if (!v.is_array() || v.size() > max || (required && v.empty()))
    throw InvalidInput(std::string("\"") + key + "\" is a list of 1 to " + std::to_string(max) + " mesh ids");
  std::vector<std::string> out;
  for (const json& id : v) {
    if (!id.is_string()) throw InvalidInput(std::string("\"") + key + "\" is a list of mesh ids");
    out.push_back(id);
  }
  return out;
}

std::string text_field(const json& body, const char* key, std::size_t max, bool required) {
  const json v = body.value(key, json(""));
  if (!v.is_string() || v.get<std::string>().size() > max || (required && v.get<std::string>().empty()))
    throw InvalidInput(std::string("\"") + key + "\" is a text of " + (required ? "1" : "0") + " to " +
                       std::to_string(max) + " bytes");
  return v;
}

// What a student reads of a run that did not end done: the kind of failure
// alone.  The run's own message is never passed on, since the student's code
// writes it while it reads a hidden mesh.
std::string student_reason(const std::string& state, const std::string& error) {
  if (state == "cancelled") return "cancelled";
  const std::string over = "exceeded its time limit of ";
  if (error.starts_with(over))
    return "time limit: it ran past " + error.substr(over.size()) +
           ", this mesh's limit (ten times the reference's run)";
  if (error.find("exceeded its memory limit") == 0) return "memory limit: it used more than the server allows";
  if (error.find("SIGSEGV") != std::string::npos) return "crashed: segmentation fault";
  if (error.find("SIGABRT") != std::string::npos) return "crashed: aborted (an uncaught exception or assert)";
  if (error.find("SIGFPE") != std::string::npos) return "crashed: arithmetic error";
  if (error.find("SIGBUS") != std::string::npos) return "crashed: bus error";
  if (error.find("killed by signal") == 0) return "crashed: killed";
  if (error.find("file-size limit") != std::string::npos) return "wrote a file over the size limit";
  return "failed: the algorithm stopped with an error (your teacher sees its message)";
}

}  // namespace

double graded_run_limit(double reference_s, double cap_s) {
  if (!(reference_s > 0)) return cap_s;
  return std::min(cap_s, std::max(1.0, 10 * reference_s));
}

double Grading::run_limit(const Assignment& a, std::size_t mesh) const {
  const double cap = a.spec.value("time_limit_s", kDefaultTimeLimit);
  const auto ref = jobs_.get(a.reference_jobs.at(mesh), Caller::local());
  return graded_run_limit(ref && ref->value("state", "") == "done" ? ref->value("run_s", 0.0) : 0.0, cap);
}

Grading::Grading(MeshService& meshes, Courses& courses, JobScheduler& jobs, PluginService& plugins)
    : meshes_(meshes), courses_(courses), jobs_(jobs), plugins_(plugins) {
  db_ = open_database(meshes.store().data_dir() / "cgview.db");
  exec_sql(db_,
           "CREATE TABLE IF NOT EXISTS assignments (id TEXT PRIMARY KEY, course TEXT NOT NULL, record TEXT NOT NULL);"
           "CREATE TABLE IF NOT EXISTS submissions (id TEXT PRIMARY KEY, assignment TEXT NOT NULL, seq INTEGER,"
           " record TEXT NOT NULL);",
           "grading");
  load();
  thread_ = std::thread([this] { loop(); });
}

Grading::~Grading() {
  stop();
  sqlite3_close(db_);
}

void Grading::stop() {
  {
    std::lock_guard lock(wake_mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Grading::wake() {
  {
    std::lock_guard lock(wake_mutex_);
    woken_ = true;
  }
  wake_.notify_all();
}

void Grading::on_job_event(const json& event) {
  const std::string type = event.value("type", "");
  if (type == "job_done" || type == "job_failed" || type == "job_cancelled") wake();
}

// ---- records ----------------------------------------------------------------

json Grading::run_json(const Run& r, bool staff) {
  json out = {{"state", r.state}, {"points", r.points}, {"reason", r.reason}};
  if (staff) {
    out["job"] = r.job;
    out["detail"] = r.detail;
    out["measures"] = r.measures;
  }
  return out;
}

json Grading::submission_json(const Submission& s, bool staff) const {
  const Assignment& a = assignments_.at(s.assignment);
  const double per = a.spec.value("points_per_mesh", 1.0);
  json runs = json::array();
  for (std::size_t i = 0; i < s.runs.size(); ++i) {
    json r = run_json(s.runs[i], staff);
    r["mesh"] = "hidden " + std::to_string(i + 1);
    r["max_points"] = per;
    if (staff) r["mesh_id"] = a.spec["hidden_meshes"][i];
    // A field is drawn on the hidden mesh (and their difference); a mesh is drawn as it is.
    const bool field = s.kind == "scalar_field";
    if ((a.spec.value("show_pictures", false) || staff) && s.runs[i].state == "done" && (field || s.kind == "mesh")) {
      const std::string at = "/api/v1/submissions/" + s.id + "/pictures/" + std::to_string(i) + "/";
      r["pictures"] = {{"result", at + "result.png"}, {"reference", at + "reference.png"}};
      if (field) r["pictures"]["difference"] = at + "difference.png";
    }
    runs.push_back(std::move(r));
  }
  json out = {{"id", s.id},
              {"assignment", s.assignment},
              {"student", s.student},
              {"created", s.created},
              {"late", s.late},
              {"state", s.state},
              {"score", s.score},
              {"max_score", per * double(s.runs.size())},
              {"build", {{"state", s.build_state}, {"error", s.error}, {"diagnostics", s.diagnostics}}},
              {"results", runs}};
  if (staff) {
    out["plugin"] = s.plugin;
    out["source"] = s.source;
    out["round"] = s.round;
  }
  return out;
}

json Grading::assignment_json(const Assignment& a, bool staff) const {
  json out = {{"id", a.id}, {"course", a.course}, {"created", a.created}, {"owner", a.owner}};
  for (const char* k : {"title", "statement", "starter", "public_meshes", "deadline", "points_per_mesh",
                        "show_pictures", "compare", "algorithm", "output", "params", "time_limit_s"})
    if (a.spec.contains(k)) out[k] = a.spec[k];
  out["hidden_count"] = a.spec["hidden_meshes"].size();
  if (staff) {
    out["hidden_meshes"] = a.spec["hidden_meshes"];
    out["reference_plugin"] = a.spec["reference_plugin"];
    out["reference_jobs"] = a.reference_jobs;
  }
  return out;
}

void Grading::save(const Assignment& a) {
  const json r = {{"id", a.id},           {"course", a.course}, {"owner", a.owner},
                  {"created", a.created}, {"spec", a.spec},     {"reference_jobs", a.reference_jobs}};
  Stmt s(db_, "INSERT OR REPLACE INTO assignments (id, course, record) VALUES (?1, ?2, ?3)");
  s.bind(1, a.id).bind(2, a.course).bind(3, r.dump());
  s.step();
}

void Grading::save(const Submission& s) {
  json runs = json::array();
  for (const Run& r : s.runs)
    runs.push_back({{"job", r.job},
                    {"compare_job", r.compare_job},
                    {"state", r.state},
                    {"points", r.points},
                    {"reason", r.reason},
                    {"detail", r.detail},
                    {"measures", r.measures}});
  const json r = {{"id", s.id},
                  {"assignment", s.assignment},
                  {"student", s.student},
                  {"created", s.created},
                  {"source", s.source},
                  {"plugin", s.plugin},
                  {"state", s.state},
                  {"build_state", s.build_state},
                  {"late", s.late},
                  {"error", s.error},
                  {"diagnostics", s.diagnostics},
                  {"runs", runs},
                  {"score", s.score},
                  {"round", s.round},
                  {"kind", s.kind},
                  {"seq", s.seq}};
  Stmt st(db_, "INSERT OR REPLACE INTO submissions (id, assignment, seq, record) VALUES (?1, ?2, ?3, ?4)");
  st.bind(1, s.id).bind(2, s.assignment).bind(3, s.seq).bind(4, r.dump());
  st.step();
}

void Grading::load() {
  {
    Stmt s(db_, "SELECT record FROM assignments");
    while (s.step()) {
      const json r = parse_json_or_discarded(s.text(0));
      if (!r.is_object()) continue;
      Assignment a{r.value("id", ""),
                   r.value("course", ""),
                   r.value("owner", ""),
                   r.value("created", ""),
                   r.value("spec", json::object()),
                   r.value("reference_jobs", std::vector<std::string>{})};
      assignments_[a.id] = a;
    }
  }
  Stmt s(db_, "SELECT record FROM submissions ORDER BY seq");
  while (s.step()) {
    const json r = parse_json_or_discarded(s.text(0));
    if (!r.is_object() || !assignments_.count(r.value("assignment", ""))) continue;
    Submission sub;
    sub.id = r.value("id", "");
    sub.assignment = r.value("assignment", "");
    sub.student = r.value("student", "");
    sub.created = r.value("created", "");
    sub.source = r.value("source", "");
    sub.plugin = r.value("plugin", "");
    sub.state = r.value("state", "building");
    sub.build_state = r.value("build_state", "building");
    sub.late = r.value("late", false);
    sub.error = r.value("error", "");
    sub.diagnostics = r.value("diagnostics", json::array());
    sub.score = r.value("score", 0.0);
    sub.round = r.value("round", 0);
    sub.kind = r.value("kind", "");
    sub.seq = r.value("seq", std::int64_t(0));
    for (const json& run : r.value("runs", json::array()))
      sub.runs.push_back({run.value("job", ""), run.value("compare_job", ""), run.value("state", "queued"),
                          run.value("points", 0.0), run.value("reason", ""), run.value("detail", ""),
                          run.value("measures", json::object())});
    seq_ = std::max(seq_, sub.seq);
    if (sub.state == "building" || sub.state == "running") pending_.insert(sub.id);
    submissions_[sub.id] = std::move(sub);
  }
}

// ---- assignments ------------------------------------------------------------

json Grading::create(const std::string& course, const json& body, const Caller& caller) {
  courses_.require_staff(course, caller, true);
  if (!body.is_object()) throw InvalidInput("the body is a JSON object (protocol/API.md, Assignments)");
  static const std::set<std::string> known = {
      "title",  "statement", "starter", "public_meshes",   "hidden_meshes", "reference_plugin", "algorithm",
      "output", "params",    "compare", "points_per_mesh", "deadline",      "show_pictures",    "time_limit_s"};
  for (const auto& [k, v] : body.items())
    if (!known.count(k)) throw InvalidInput("an assignment has no \"" + k + "\"");
  json spec = json::object();
  spec["title"] = text_field(body, "title", 200, true);
  spec["statement"] = text_field(body, "statement", kMaxStatement, false);
  spec["starter"] = text_field(body, "starter", kMaxStarter, false);
  const auto pub = id_list(body, "public_meshes", kMaxPublic, false);
  const auto hidden = id_list(body, "hidden_meshes", kMaxHidden, true);
  Store& store = meshes_.store();
  for (const auto& id : pub) {
    const auto rec = store.get_mesh(id, caller);
    if (!rec) throw std::out_of_range("no mesh with id '" + id + "'");
    // Posting shares it with the course: only its owner shares a mesh.
    if (!Access{rec->owner}.owned_by(caller) && !store.access("mesh", id, rec->owner).everyone)
      throw Forbidden("public mesh " + id + " is " + rec->owner + "'s: only its owner shares it with a course");
  }
  for (const auto& id : hidden) {
    const auto rec = store.get_mesh(id, caller);
    if (!rec) throw std::out_of_range("no mesh with id '" + id + "'");
    if (!Access{rec->owner}.owned_by(caller))
      throw InvalidInput("hidden mesh " + id + " is " + rec->owner + "'s: a hidden mesh is one of your own");
    // Shared with nobody but courses' staff (an earlier assignment's, or this one's).
    const Access a = store.access("mesh", id, rec->owner);
    for (const std::string& r : a.readers)
      if (!r.starts_with("staff:"))
        throw InvalidInput("hidden mesh " + id + " is shared (with " + r + "): unshare it first, or it is not hidden");
    if (a.everyone)
      throw InvalidInput("hidden mesh " + id + " is shared (with everyone): unshare it first, or it is not hidden");
    if (std::find(pub.begin(), pub.end(), id) != pub.end())
      throw InvalidInput("mesh " + id + " is both public and hidden");
  }
  spec["public_meshes"] = pub;
  spec["hidden_meshes"] = hidden;
  if (!body.value("reference_plugin", json()).is_string())
    throw InvalidInput("\"reference_plugin\" is the id of your built plugin that solves the assignment");
  spec["reference_plugin"] = body["reference_plugin"];
  // The reference's algorithm: the one named, or the plugin's only one.
  const json plugin = plugins_.get(spec["reference_plugin"], caller);
  const json algos = plugin["build"].value("algorithms", json::array());
  if (plugin["build"].value("state", "") != "ok" || algos.empty())
    throw InvalidInput("reference plugin " + spec["reference_plugin"].get<std::string>() +
                       " is not built: build it first (its state: " + plugin["build"].value("state", "") + ")");
  std::string algorithm = body.value("algorithm", json("")).is_string() ? body.value("algorithm", "") : "";
  if (algorithm.empty()) {
    if (algos.size() != 1) throw InvalidInput("the reference plugin has several algorithms: name one in \"algorithm\"");
    algorithm = algos[0];
  }
  spec["algorithm"] = algorithm;
  const PluginAlgorithm resolved = plugins_.resolve(spec["reference_plugin"], algorithm, caller);
  const json outputs = resolved.description.value("outputs", json::array());
  if (outputs.empty()) throw InvalidInput("algorithm '" + algorithm + "' declares no outputs to compare");
  std::string output = body.value("output", json("")).is_string() ? body.value("output", "") : "";
  std::string kind;
  for (const json& o : outputs)
    if (output.empty() || o.value("name", "") == output) {
      output = o.value("name", ""), kind = o.value("kind", "");
      break;
    }
  if (kind.empty()) throw InvalidInput("algorithm '" + algorithm + "' has no output '" + output + "'");
  spec["output"] = output;
  spec["kind"] = kind;
  spec["compare"] = to_json(compare_spec_from_json(body.value("compare", json::object()), kind_named(kind)));
  const json params = body.value("params", json::object());
  if (!params.is_object()) throw InvalidInput("\"params\" is the algorithm's parameters, a JSON object");
  spec["params"] = params;
  const json points = body.value("points_per_mesh", json(1));
  if (!points.is_number() || points.get<double>() <= 0 || points.get<double>() > 1000)
    throw InvalidInput("\"points_per_mesh\" is a number in (0, 1000]");
  spec["points_per_mesh"] = points;
  const json limit = body.value("time_limit_s", json(kDefaultTimeLimit));
  if (!limit.is_number() || limit.get<double>() < 1 || limit.get<double>() > 3600)
    throw InvalidInput("\"time_limit_s\" is a number of seconds in [1, 3600]");
  spec["time_limit_s"] = limit;
  const json deadline = body.value("deadline", json(nullptr));
  if (!deadline.is_null() && (!deadline.is_string() || !iso_time(deadline)))
    throw InvalidInput("\"deadline\" is a UTC time such as \"2026-12-01T23:59:00Z\"");
  spec["deadline"] = deadline;
  const json pictures = body.value("show_pictures", json(false));
  if (!pictures.is_boolean()) throw InvalidInput("\"show_pictures\" is true or false");
  spec["show_pictures"] = pictures;

  Assignment a{new_id(), course, caller.user, now_iso8601(), spec, {}};
  // The reference on every hidden mesh, as the teacher's own jobs: the staff read them.
  for (const auto& id : hidden) {
    const json job = jobs_.submit({{"algorithm", algorithm},
                                   {"plugin", spec["reference_plugin"]},
                                   {"inputs", {{"mesh", id}}},
                                   {"params", params}},
                                  caller);
    a.reference_jobs.push_back(job["id"]);
    store.set_shared("job", job["id"], {Courses::staff(course)}, true);
  }
  // The public meshes are the course's to read; the hidden ones its staff's (they open the runs on them).
  for (const auto& id : pub) store.set_shared("mesh", id, {Courses::group(course)}, true);
  for (const auto& id : hidden) store.set_shared("mesh", id, {Courses::staff(course)}, true);
  std::lock_guard lock(mutex_);
  save(a);
  assignments_[a.id] = a;
  return assignment_json(a, true);
}

const Grading::Assignment& Grading::assignment_locked(const std::string& id, const Caller& caller, bool staff) const {
  const auto it = assignments_.find(id);
  if (it == assignments_.end() || !courses_.role(it->second.course, caller))
    throw std::out_of_range("no assignment with id '" + id + "'");
  if (staff) courses_.require_staff(it->second.course, caller);
  return it->second;
}

json Grading::list(const std::string& course, const Caller& caller) const {
  const std::string role = courses_.require_member(course, caller);
  std::lock_guard lock(mutex_);
  json out = json::array();
  for (const auto& [id, a] : assignments_)
    if (a.course == course) out.push_back(assignment_json(a, role != "student"));
  std::sort(out.begin(), out.end(), [](const json& x, const json& y) { return x["created"] < y["created"]; });
  return out;
}

json Grading::get(const std::string& id, const Caller& caller) const {
  std::lock_guard lock(mutex_);
  const Assignment& a = assignment_locked(id, caller, false);
  return assignment_json(a, courses_.role(a.course, caller) != "student");
}

// ---- submissions ------------------------------------------------------------

json Grading::submit(const std::string& assignment, const json& body, const Caller& caller) {
  std::string course, deadline;
  std::size_t hidden = 0;
  {
    std::lock_guard lock(mutex_);
    const Assignment& a = assignment_locked(assignment, caller, false);
    course = a.course;
    deadline = a.spec.value("deadline", json(nullptr)).is_string() ? a.spec["deadline"].get<std::string>() : "";
    hidden = a.spec["hidden_meshes"].size();
  }
  if (!body.is_object()) throw InvalidInput("the body is {\"source\": C++ TEXT} or {\"plugin\": YOUR PLUGIN'S ID}");
  std::string source;
  if (body.contains("plugin")) {
    if (!body["plugin"].is_string()) throw InvalidInput("\"plugin\" is a plugin's id");
    source = plugins_.get(body["plugin"], caller).value("source", "");
  } else if (body.value("source", json()).is_string()) {
    source = body["source"];
  } else {
    throw InvalidInput("the body is {\"source\": C++ TEXT} or {\"plugin\": YOUR PLUGIN'S ID}");
  }
  // The submission's own copy of the source, the grader's: what the student
  // changes afterwards changes nothing graded.
  const Caller g{grader(caller.user), true};
  const json plugin = plugins_.create({{"name", "submission"}, {"source", source}}, g);
  Submission s;
  s.id = new_id();
  s.assignment = assignment;
  s.student = caller.user;
  s.created = now_iso8601();
  s.source = source;
  s.plugin = plugin["id"];
  s.late = !deadline.empty() && s.created > deadline;
  s.runs.resize(hidden);
  {
    std::lock_guard lock(mutex_);
    s.seq = ++seq_;
    save(s);
    submissions_[s.id] = s;
    pending_.insert(s.id);
  }
  try {
    plugins_.build(s.plugin, g);
  } catch (const std::exception& e) {
    std::lock_guard lock(mutex_);
    Submission& stored = submissions_.at(s.id);
    stored.state = stored.build_state = "failed";
    stored.error = e.what();
    pending_.erase(s.id);
    save(stored);
  }
  wake();
  std::lock_guard lock(mutex_);
  return submission_json(submissions_.at(s.id), courses_.role(course, caller) != "student");
}

json Grading::submission(const std::string& id, const Caller& caller) const {
  std::lock_guard lock(mutex_);
  const auto it = submissions_.find(id);
  if (it == submissions_.end()) throw std::out_of_range("no submission with id '" + id + "'");
  const Assignment& a = assignments_.at(it->second.assignment);
  const auto role = courses_.role(a.course, caller);
  const bool staff = role && *role != "student";
  if (!staff && it->second.student != caller.user) throw std::out_of_range("no submission with id '" + id + "'");
  return submission_json(it->second, staff);
}

json Grading::submissions(const std::string& assignment, const Caller& caller) const {
  std::lock_guard lock(mutex_);
  const Assignment& a = assignment_locked(assignment, caller, false);
  const bool staff = courses_.role(a.course, caller) != "student";
  std::vector<const Submission*> list;
  for (const auto& [id, s] : submissions_)
    if (s.assignment == assignment && (staff || s.student == caller.user)) list.push_back(&s);
  std::sort(list.begin(), list.end(), [](auto* x, auto* y) { return x->seq < y->seq; });
  json out = json::array();
  for (const Submission* s : list) {
    json j = submission_json(*s, staff);
    j.erase("source");
    out.push_back(std::move(j));
  }
  return out;
}

json Grading::regrade(const std::string& assignment, const Caller& caller) {
  std::lock_guard lock(mutex_);
  const Assignment& a = assignment_locked(assignment, caller, true);
  std::size_t n = 0;
  for (auto& [id, s] : submissions_) {
    if (s.assignment != a.id || s.build_state == "failed") continue;
    ++s.round;
    s.state = "running";
    for (Run& r : s.runs) r = Run{};
    s.score = 0;
    save(s);
    pending_.insert(id);
    ++n;
  }
  wake();
  return {{"assignment", assignment}, {"regrading", n}};
}

// ---- grading ----------------------------------------------------------------

void Grading::loop() {
  for (;;) {
    {
      std::unique_lock lock(wake_mutex_);
      // Also every second: an event that came before its job was known here is not lost.
      wake_.wait_for(lock, std::chrono::seconds(1), [this] { return woken_ || stopping_; });
      if (stopping_) return;
      woken_ = false;
    }
    std::vector<std::string> ids;
    {
      std::lock_guard lock(mutex_);
      ids.assign(pending_.begin(), pending_.end());
    }
    // Oldest first, each a step at a time: no submission waits behind another's comparison.
    for (const auto& id : ids) {
      try {
        advance(id);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "cgview-server: grading submission %s: %s\n", id.c_str(), e.what());
      }
      {
        std::lock_guard lock(wake_mutex_);
        if (stopping_) return;
      }
    }
  }
}

void Grading::advance(const std::string& id) {
  Submission s;
  Assignment a;
  {
    std::lock_guard lock(mutex_);
    const auto it = submissions_.find(id);
    if (it == submissions_.end()) return;
    s = it->second;
    a = assignments_.at(s.assignment);
  }
  const Caller g{grader(s.student), true};
  const int round = s.round;
  bool changed = false;
  if (s.state == "building") {
    const json p = plugins_.get(s.plugin, g);
    const std::string state = p["build"].value("state", "");
    if (state == "building" || state == "none") return;
    s.diagnostics = p["build"].value("diagnostics", json::array());
    if (state != "ok") {
      s.state = s.build_state = "failed";
      s.error = p["build"].value("error", json("")).is_string() ? p["build"].value("error", "") : "";
      if (s.error.empty()) s.error = "it did not compile";
      for (Run& r : s.runs) r.state = "failed", r.reason = "did not compile";
    } else {
      s.build_state = "ok";
      s.state = "running";
    }
    changed = true;
  }
  if (s.state == "running") {
    const json p = plugins_.get(s.plugin, g);
    const json algos = p["build"].value("algorithms", json::array());
    std::string algorithm = a.spec["algorithm"];
    if (std::find(algos.begin(), algos.end(), json(algorithm)) == algos.end() && algos.size() == 1)
      algorithm = algos[0];
    bool all_ended = true;
    for (std::size_t i = 0; i < s.runs.size(); ++i) {
      Run& r = s.runs[i];
      if (r.state == "done" || r.state == "failed") continue;
      if (r.job.empty()) {
        try {
          const json job = jobs_.submit({{"algorithm", algorithm},
                                         {"plugin", s.plugin},
                                         {"inputs", {{"mesh", a.spec["hidden_meshes"][i]}}},
                                         {"params", a.spec["params"]},
                                         {"timeout_s", run_limit(a, i)}},
                                        g, nullptr, true);
          r.job = job["id"];
          meshes_.store().set_shared("job", r.job, {Courses::staff(a.course)}, true);
          r.state = "running";
        } catch (const std::exception& e) {
          r.state = "failed";
          r.reason = "could not run: it has no algorithm '" + algorithm + "' taking the assignment's parameters";
          r.detail = e.what();
        }
        changed = true;
        if (r.state == "failed") continue;
      }
      const auto job = jobs_.get(r.job, g);
      const std::string state = job ? job->value("state", "") : "cancelled";
      if (state == "queued" || state == "running") {
        all_ended = false;
        continue;
      }
      if (state != "done") {
        r.state = "failed";
        r.detail = job ? job->value("error", "") : "the run is gone";
        r.reason = student_reason(state, r.detail);
        changed = true;
        continue;
      }
      const std::string& ref_id = a.reference_jobs.at(i);
      const auto ref = jobs_.get(ref_id, Caller::local());
      const std::string ref_state = ref ? ref->value("state", "") : "gone";
      if (ref_state == "queued" || ref_state == "running") {
        all_ended = false;
        continue;
      }
      if (ref_state != "done") {
        changed = true;
        r.state = "done";
        r.points = 0;
        r.reason = "not graded: the reference has no output on this mesh (your teacher is told)";
        r.detail = "reference job " + ref_id + ": " + (ref ? ref->value("error", "") : "gone");
        continue;
      }
      const OutputKind kind = kind_named(a.spec["kind"]);
      const std::string output = a.spec["output"];
      const double points = a.spec.value("points_per_mesh", 1.0);
      if (kind == OutputKind::mesh || kind == OutputKind::skeleton) {
        // What a mesh or a skeleton costs to compare depends on its shape,
        // which the student's code made: measured in the sandbox, as a job.
        if (r.compare_job.empty()) {
          changed = true;
          try {
            const json c =
                jobs_.submit({{"algorithm", kind == OutputKind::mesh ? "compare_meshes" : "compare_skeletons"},
                              {"inputs",
                               {{"result", {{"job", r.job}, {"artifact", output}}},
                                {"reference", {{"job", ref_id}, {"artifact", output}}}}},
                              {"params", {{"spec", a.spec["compare"].dump()}}},
                              {"timeout_s", a.spec["time_limit_s"]}},
                             g, nullptr, true);
            r.compare_job = c["id"];
            meshes_.store().set_shared("job", r.compare_job, {Courses::staff(a.course)}, true);
          } catch (const std::exception& e) {
            r.state = "done";
            r.points = 0;
            r.reason = "no output '" + output + "' of kind " + to_string(kind);
            r.detail = e.what();
            continue;
          }
        }
        const auto c = jobs_.get(r.compare_job, g);
        const std::string compared = c ? c->value("state", "") : "gone";
        if (compared == "queued" || compared == "running") {
          all_ended = false;
          continue;
        }
        changed = true;
        r.state = "done";
        r.points = 0;
        try {
          if (compared != "done") throw std::runtime_error(c ? c->value("error", "") : "the comparison is gone");
          const json v = parse_json_or_discarded(
              std::get<Text>(jobs_.artifact_value(r.compare_job, "verdict", OutputKind::text, Caller::local())).bytes);
          if (!v.is_object()) throw std::runtime_error("the comparison's verdict is not JSON");
          r.points = v.value("pass", false) ? points : 0;
          r.reason = v.value("reason", "");
          r.measures = v.value("measures", json::object());
        } catch (const std::exception& e) {
          r.reason = "not graded: its output could not be compared with the reference's within the limits";
          r.detail = e.what();
        }
        continue;
      }
      changed = true;
      r.state = "done";
      try {
        const CompareSpec cmp = compare_spec_from_json(a.spec["compare"], kind);
        const ArtifactValue reference = jobs_.artifact_value(ref_id, output, kind, Caller::local());
        ArtifactValue result;
        try {
          result = jobs_.artifact_value(r.job, output, kind, Caller::local());
        } catch (const std::exception&) {
          r.points = 0;
          r.reason = "no output '" + output + "' of kind " + to_string(kind);
          continue;
        }
        const Verdict v = compare_output(result, reference, cmp);
        r.points = v.pass ? points : 0;
        r.reason = v.reason;
        r.measures = v.measures;
      } catch (const std::exception& e) {
        r.points = 0;
        r.reason = "not graded: the comparison failed (your teacher is told)";
        r.detail = e.what();
      }
    }
    if (all_ended) {
      s.state = "graded";
      s.kind = a.spec.value("kind", "");
      s.score = 0;
      for (const Run& r : s.runs) s.score += r.points;
      changed = true;
    }
  }
  if (!changed) return;
  std::lock_guard lock(mutex_);
  const auto it = submissions_.find(id);
  // Graded again meanwhile: that round's steps win.
  if (it == submissions_.end() || it->second.round != round) return;
  it->second = s;
  if (s.state == "graded" || s.state == "failed") pending_.erase(id);
  save(s);
}

// ---- grades -----------------------------------------------------------------

json Grading::grades(const std::string& assignment, bool late, const Caller& caller) const {
  std::string course;
  {
    std::lock_guard lock(mutex_);
    course = assignment_locked(assignment, caller, true).course;
  }
  const auto students = courses_.students(course);
  std::lock_guard lock(mutex_);
  const Assignment& a = assignments_.at(assignment);
  const double max = a.spec.value("points_per_mesh", 1.0) * double(a.spec["hidden_meshes"].size());
  json rows = json::array();
  for (const auto& [login, name] : students) {
    const Submission* counted = nullptr;
    int count = 0;
    for (const auto& [id, s] : submissions_) {
      if (s.assignment != assignment || s.student != login) continue;
      ++count;
      if ((late || !s.late) && (!counted || s.seq > counted->seq)) counted = &s;
    }
    json row = {{"login", login}, {"name", name}, {"submissions", count}, {"max_score", max}};
    if (counted) {
      row["score"] = counted->state == "graded" || counted->state == "failed" ? json(counted->score) : json(nullptr);
      row["state"] = counted->state;
      row["submission"] = counted->id;
      row["submitted"] = counted->created;
      row["late"] = counted->late;
    } else {
      row["score"] = nullptr;
    }
    rows.push_back(std::move(row));
  }
  return {{"assignment", assignment},
          {"title", a.spec["title"]},
          {"late_counted", late},
          {"max_score", max},
          {"students", rows}};
}

namespace {
std::string csv_cell(const std::string& v) {
  if (v.find_first_of(",\"\n\r") == std::string::npos) return v;
  std::string out = "\"";
  for (char c : v) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}
std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}
}  // namespace

std::string Grading::grades_csv(const std::string& assignment, bool late, const Caller& caller) const {
  const json g = grades(assignment, late, caller);
  // Canvas's gradebook import matches a row by "SIS Login ID" (or ID), Moodle's
  // by a column the teacher maps to "username"; both take the assignment's
  // column by its title, and ignore the columns they do not know.
  const std::string title = g["title"].get<std::string>() + " (" + number_text(g["max_score"]) + " points)";
  std::string out = "Student,ID,SIS User ID,SIS Login ID,Section," + csv_cell(title) + ",Submissions,Submitted,Late\n";
  for (const json& r : g["students"]) {
    const std::string name = r.value("name", "").empty() ? r.value("login", "") : r.value("name", "");
    out += csv_cell(name) + ",," + csv_cell(r["login"]) + "," + csv_cell(r["login"]) + ",,";
    out += r["score"].is_number() ? number_text(r["score"]) : "";
    out += "," + std::to_string(r["submissions"].get<int>()) + "," + csv_cell(r.value("submitted", "")) + "," +
           (r.value("late", false) ? "yes" : "") + "\n";
  }
  return out;
}

// ---- pictures ---------------------------------------------------------------

Grading::Picture Grading::picture(const std::string& id, std::size_t n, const std::string& which,
                                  const Caller& caller) const {
  std::string job, ref_job, output, mesh_id, kind;
  {
    std::lock_guard lock(mutex_);
    const auto it = submissions_.find(id);
    if (it == submissions_.end()) throw std::out_of_range("no submission with id '" + id + "'");
    const Submission& s = it->second;
    const Assignment& a = assignments_.at(s.assignment);
    const auto role = courses_.role(a.course, caller);
    const bool staff = role && *role != "student";
    if (!staff && s.student != caller.user) throw std::out_of_range("no submission with id '" + id + "'");
    if (!staff && !a.spec.value("show_pictures", false))
      throw Forbidden("this assignment shows no pictures of results on its hidden meshes");
    if (n >= s.runs.size()) throw std::out_of_range("submission " + id + " has no result " + std::to_string(n));
    kind = a.spec.value("kind", "");
    if (s.runs[n].state != "done" || s.runs[n].job.empty() || (kind != "scalar_field" && kind != "mesh"))
      throw InvalidInput("result " + std::to_string(n) + " has no field or mesh to show");
    job = s.runs[n].job;
    ref_job = a.reference_jobs.at(n);
    output = a.spec["output"];
    mesh_id = a.spec["hidden_meshes"][n];
  }
  if (kind == "mesh") {
    if (which != "result" && which != "reference")
      throw std::out_of_range("no picture '" + which + "' of a mesh: result or reference");
    const ArtifactValue v =
        jobs_.artifact_value(which == "result" ? job : ref_job, output, OutputKind::mesh, Caller::local());
    return {std::make_shared<const Mesh>(std::get<Mesh>(v)), std::nullopt};
  }
  const auto rec = meshes_.store().get_mesh(mesh_id, Caller::local());
  if (!rec) throw std::out_of_range("the hidden mesh is gone");
  Picture p{meshes_.mesh(*rec), ScalarField{}};
  auto field = [&](const std::string& j) {
    return std::get<ScalarField>(jobs_.artifact_value(j, output, OutputKind::scalar_field, Caller::local()));
  };
  if (which == "result") p.field = field(job);
  else if (which == "reference") p.field = field(ref_job);
  else if (which == "difference") {
    ScalarField d = field(job);
    const ScalarField ref = field(ref_job);
    if (ref.values.size() != d.values.size()) throw InvalidInput("the result and the reference differ in size");
    for (std::size_t i = 0; i < ref.values.size(); ++i) d.values[i] = std::abs(d.values[i] - ref.values[i]);
    d.name = "difference";
    p.field = std::move(d);
  } else {
    throw std::out_of_range("no picture '" + which + "': result, reference or difference");
  }
  p.field->check_matches(*p.mesh);
  return p;
}

}  // namespace cgview::server
