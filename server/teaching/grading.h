// Assignments and their grading: a course's exercise, graded on meshes its
// students never see.
//
// A teacher posts an assignment: a statement (Markdown), a starter file,
// public meshes (shared with the course), hidden meshes (the teacher's,
// shared with nobody), a reference solution (a built plugin of the
// teacher's), which output is compared and how (compare/compare_output.h),
// points per hidden mesh, a deadline, and whether students see pictures of
// their results.  Posting runs the reference on every hidden mesh.
//
// A submission is a plugin's source, snapshotted.  It is built and run by
// the ordinary job system, as a user of its own, "grading:STUDENT" (not a
// user name any person can have), so that:
//   - the fair queue takes students in turn (one student's twenty
//     submissions do not hold up another's first);
//   - the builds and runs are cached by content (the same source is built
//     once; the same submission graded again gets the same scores);
//   - its runs and their outputs are the course staff's to read (shared with
//     "staff:COURSE") and never the student's: a student reads a submission
//     only as scores, reasons that carry no text of the run, and, where the
//     teacher allows it, pictures from the renderer.
// Grading proceeds on its own thread, woken by job events and every second,
// so that nothing runs on the scheduler's thread.
#pragma once

#include <condition_variable>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/mesh.h"
#include "core/scalar_field.h"
#include "store.h"

struct sqlite3;

namespace cgview::server {

class Courses;
class JobScheduler;
class MeshService;
class PluginService;

// A graded run's time limit: ten times the reference's own run on that mesh
// (REFERENCE_S, 0 when not known), at least 1 s, and never over the
// teacher's limit CAP_S, which alone holds while the reference's time is not
// known.  So a looping submission costs a few seconds of a worker, not the
// teacher's minute, and a right one slower than the reference still passes.
double graded_run_limit(double reference_s, double cap_s);

class Grading {
 public:
  Grading(MeshService& meshes, Courses& courses, JobScheduler& jobs, PluginService& plugins);
  ~Grading();
  Grading(const Grading&) = delete;
  Grading& operator=(const Grading&) = delete;

  // POST /api/v1/courses/{id}/assignments (a teacher of the course).  Throws
  // InvalidInput naming what is wrong, Forbidden, std::out_of_range.
  nlohmann::json create(const std::string& course, const nlohmann::json& body, const Caller& caller);
  // A course's assignments, as its members see them.
  nlohmann::json list(const std::string& course, const Caller& caller) const;
  // One assignment: what a student reads (title, statement, starter, public
  // meshes, deadline, points); its staff also the hidden meshes, the
  // reference and its runs.
  nlohmann::json get(const std::string& id, const Caller& caller) const;
  // A student's submission: {"source"} or {"plugin": an id they read}.
  nlohmann::json submit(const std::string& assignment, const nlohmann::json& body, const Caller& caller);
  // One submission: its student and the course's staff.
  nlohmann::json submission(const std::string& id, const Caller& caller) const;
  // An assignment's submissions: a student's own; the staff's, all (with sources left out).
  nlohmann::json submissions(const std::string& assignment, const Caller& caller) const;
  // The grades (staff): a row per student of the course; `late` says whether
  // a late submission counts (else the latest one before the deadline does).
  nlohmann::json grades(const std::string& assignment, bool late, const Caller& caller) const;
  // The same as CSV, with the columns the gradebook imports of Moodle and
  // Canvas match students by.
  std::string grades_csv(const std::string& assignment, bool late, const Caller& caller) const;
  // Grades every submission again (staff): their runs are cached, so an
  // unchanged one gets the same scores.
  nlohmann::json regrade(const std::string& assignment, const Caller& caller);

  // What a picture of a submission's result on hidden mesh `n` shows:
  // which: "result", "reference" or "difference" (a field's: on the hidden
  // mesh); a mesh output's result or reference, drawn as it is.  Throws
  // std::out_of_range, Forbidden (pictures are off for students), InvalidInput
  // (the output is not a scalar field, or the run has none).
  struct Picture {
    std::shared_ptr<const Mesh> mesh;
    std::optional<ScalarField> field;  // none: the mesh as it is
  };
  Picture picture(const std::string& submission, std::size_t n, const std::string& which, const Caller& caller) const;

  // A job's event (the scheduler's on_event): wakes the grading thread.
  void on_job_event(const nlohmann::json& event);
  // Stops the grading thread (before the scheduler goes).
  void stop();

 private:
  struct Assignment {
    std::string id, course, owner, created;
    nlohmann::json spec;                      // what the teacher posted, checked
    std::vector<std::string> reference_jobs;  // one per hidden mesh
  };
  struct Run {
    std::string job;               // "" until submitted
    std::string compare_job;       // a mesh's or skeleton's comparison, run as a job of its own
    std::string state = "queued";  // queued, running, done, failed
    double points = 0;
    std::string reason, detail;  // reason: the student's; detail: the staff's (the run's own error)
    nlohmann::json measures = nlohmann::json::object();
  };
  struct Submission {
    std::string id, assignment, student, created, source, plugin;
    std::string state = "building";        // building, running, graded, failed (did not build)
    std::string build_state = "building";  // building, ok, failed
    std::string kind;                      // of the output compared, once graded
    std::int64_t seq = 0;                  // submission order
    bool late = false;
    std::string error;  // a build that failed: the compiler's first message
    nlohmann::json diagnostics = nlohmann::json::array();
    std::vector<Run> runs;  // one per hidden mesh
    double score = 0;
    int round = 0;  // grade-again count
  };
  static std::string grader(const std::string& student) { return "grading:" + student; }
  static nlohmann::json run_json(const Run& r, bool staff);
  // A run's time limit on hidden mesh MESH (graded_run_limit).
  double run_limit(const Assignment& a, std::size_t mesh) const;
  void wake();
  nlohmann::json assignment_json(const Assignment& a, bool staff) const;
  nlohmann::json submission_json(const Submission& s, bool staff) const;
  const Assignment& assignment_locked(const std::string& id, const Caller& caller, bool staff) const;
  void save(const Assignment& a);
  void save(const Submission& s);
  void load();
  // One step of a submission's grading (on the grading thread, without mutex_).
  void advance(const std::string& id);
  void loop();

  MeshService& meshes_;
  Courses& courses_;
  JobScheduler& jobs_;
  PluginService& plugins_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
  std::map<std::string, Assignment> assignments_;
  std::map<std::string, Submission> submissions_;
  std::vector<std::string> order_;  // submission ids, oldest first
  std::set<std::string> pending_;   // submissions not graded yet
  std::int64_t seq_ = 0;
  // The grading thread's wake-up, apart from mutex_ (held while the grading
  // thread calls no one): a job event never waits for a submission's step.
  std::mutex wake_mutex_;
  std::condition_variable wake_;
  bool woken_ = false, stopping_ = false;
  std::thread thread_;
};

}  // namespace cgview::server
