#include "jobs/job_store.h"

#include <sqlite3.h>

#include "core/errors.h"
#include "io/parse_json.h"
#include "store.h"

namespace cgview::server {

using nlohmann::json;

JobStore::JobStore(const std::filesystem::path& data_dir) {
  db_ = open_database(data_dir / "cgview.db");
  exec_sql(db_,
           "CREATE TABLE IF NOT EXISTS jobs ("
           " id TEXT PRIMARY KEY, seq INTEGER NOT NULL, owner TEXT NOT NULL, algorithm TEXT NOT NULL,"
           " mesh_id TEXT NOT NULL, mesh_sha TEXT NOT NULL, params TEXT NOT NULL, cache_key TEXT NOT NULL,"
           " state TEXT NOT NULL, stage TEXT NOT NULL, progress REAL NOT NULL, error TEXT NOT NULL,"
           " cached INTEGER NOT NULL, created TEXT NOT NULL, started TEXT NOT NULL, finished TEXT NOT NULL,"
           " artifacts TEXT NOT NULL, files TEXT NOT NULL, inputs TEXT NOT NULL DEFAULT '{}', bytes INTEGER,"
           " executor TEXT NOT NULL DEFAULT '', handle TEXT NOT NULL DEFAULT '', worker_token TEXT NOT NULL DEFAULT '',"
           " warnings TEXT NOT NULL DEFAULT '[]');"
           "CREATE INDEX IF NOT EXISTS jobs_cache ON jobs(cache_key);",
           "jobs");
  // A database from before algorithms of several inputs lacks the column.
  add_missing_column(db_, "jobs", "inputs", "TEXT NOT NULL DEFAULT '{}'", "jobs");
  // One from before result sizes were stored: NULL until the scheduler sizes the job once.
  add_missing_column(db_, "jobs", "bytes", "INTEGER", "jobs");
  // One from before executors: every job ran locally.
  add_missing_column(db_, "jobs", "executor", "TEXT NOT NULL DEFAULT ''", "jobs");
  add_missing_column(db_, "jobs", "handle", "TEXT NOT NULL DEFAULT ''", "jobs");
  add_missing_column(db_, "jobs", "worker_token", "TEXT NOT NULL DEFAULT ''", "jobs");
  // One from before a job's warnings were kept.
  add_missing_column(db_, "jobs", "warnings", "TEXT NOT NULL DEFAULT '[]'", "jobs");
  // One from before plugins.
  add_missing_column(db_, "jobs", "plugin", "TEXT NOT NULL DEFAULT ''", "jobs");
  // One from before runs were timed.
  add_missing_column(db_, "jobs", "run_s", "REAL NOT NULL DEFAULT 0", "jobs");
}

JobStore::~JobStore() { sqlite3_close(db_); }

std::vector<std::shared_ptr<Job>> JobStore::load() const {
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(
      db_,
      "SELECT id, seq, owner, algorithm, mesh_id, mesh_sha, params, cache_key, state, stage, progress,"
      " error, cached, created, started, finished, artifacts, files, inputs, bytes, executor, handle, worker_token,"
      " warnings, plugin, run_s FROM jobs ORDER BY seq",
      -1, &s, nullptr);
  auto text = [&](int c) {
    const auto* p = sqlite3_column_text(s, c);
    return p ? std::string(reinterpret_cast<const char*>(p)) : std::string();
  };
  std::vector<std::shared_ptr<Job>> out;
  while (sqlite3_step(s) == SQLITE_ROW) {
    auto j = std::make_shared<Job>();
    j->id = text(0);
    j->seq = sqlite3_column_int64(s, 1);
    j->owner = text(2);
    j->algorithm = text(3);
    j->mesh_id = text(4);
    j->mesh_sha = text(5);
    j->params = parse_json_or_discarded(text(6));
    if (!j->params.is_object()) j->params = json::object();
    j->cache_key = text(7);
    j->state = job_state_from(text(8)).value_or(JobState::failed);
    j->stage = text(9);
    j->progress = sqlite3_column_double(s, 10);
    j->error = text(11);
    j->cached = sqlite3_column_int(s, 12) != 0;
    j->created = text(13);
    j->started = text(14);
    j->finished = text(15);
    j->artifacts = parse_json_or_discarded(text(16));
    if (!j->artifacts.is_array()) j->artifacts = json::array();
    j->files = text(17);
    // A job from before several inputs has only its mesh.
    j->inputs = parse_json_or_discarded(text(18));
    if (!j->inputs.is_object()) j->inputs = json::object();
    if (j->inputs.empty() && !j->mesh_id.empty()) j->inputs = {{"mesh", j->mesh_id}};
    // NULL: not sized yet (the scheduler sizes it once); in_flight marks that here.
    if (sqlite3_column_type(s, 19) != SQLITE_NULL) j->bytes = std::uint64_t(sqlite3_column_int64(s, 19));
    else j->in_flight = true;
    j->executor = text(20);
    j->handle = text(21);
    j->worker_token_sha = text(22);
    j->warnings = parse_json_or_discarded(text(23));
    if (!j->warnings.is_array()) j->warnings = json::array();
    j->plugin = parse_json_or_discarded(text(24));
    if (!j->plugin.is_object()) j->plugin = nullptr;
    j->run_s = sqlite3_column_double(s, 25);
    out.push_back(std::move(j));
  }
  sqlite3_finalize(s);
  return out;
}

void JobStore::put(const Job& j) {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(
          db_,
          "INSERT OR REPLACE INTO jobs (id, seq, owner, algorithm, mesh_id, mesh_sha, params, cache_key,"
          " state, stage, progress, error, cached, created, started, finished, artifacts, files, inputs,"
          " bytes, executor, handle, worker_token, warnings, plugin, run_s)"
          " VALUES (?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11,?12,?13,?14,?15,?16,?17,?18,?19,?20,?21,?22,?23,?24,?25,?26)",
          -1, &s, nullptr) != SQLITE_OK)
    throw IoError(std::string("jobs: ") + sqlite3_errmsg(db_));
  int i = 0;
  auto t = [&](const std::string& v) { sqlite3_bind_text(s, ++i, v.data(), int(v.size()), SQLITE_TRANSIENT); };
  t(j.id);
  sqlite3_bind_int64(s, ++i, j.seq);
  t(j.owner), t(j.algorithm), t(j.mesh_id), t(j.mesh_sha), t(j.params.dump()), t(j.cache_key), t(to_string(j.state)),
      t(j.stage);
  sqlite3_bind_double(s, ++i, j.progress);
  t(j.error);
  sqlite3_bind_int(s, ++i, j.cached ? 1 : 0);
  t(j.created), t(j.started), t(j.finished), t(j.artifacts.dump()), t(j.files), t(j.inputs.dump());
  // Unsized (NULL) while its worker may still write: a start after a crash
  // sizes it then (a running job cancelled is sized when its worker ends).
  if (active(j.state) || j.in_flight) sqlite3_bind_null(s, ++i);
  else sqlite3_bind_int64(s, ++i, std::int64_t(j.bytes));
  t(j.executor), t(j.handle), t(j.worker_token_sha), t(j.warnings.dump());
  t(j.plugin.is_object() ? j.plugin.dump() : std::string());
  sqlite3_bind_double(s, ++i, j.run_s);
  const int rc = sqlite3_step(s);
  sqlite3_finalize(s);
  if (rc == SQLITE_FULL) throw DiskFull(std::string("jobs: ") + sqlite3_errmsg(db_));
  if (rc != SQLITE_DONE) throw IoError(std::string("jobs: ") + sqlite3_errmsg(db_));
}

void JobStore::remove(const std::string& id) {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(db_, "DELETE FROM jobs WHERE id = ?1", -1, &s, nullptr) != SQLITE_OK)
    throw IoError(std::string("jobs: ") + sqlite3_errmsg(db_));
  sqlite3_bind_text(s, 1, id.data(), int(id.size()), SQLITE_TRANSIENT);
  const int rc = sqlite3_step(s);
  sqlite3_finalize(s);
  if (rc == SQLITE_FULL) throw DiskFull(std::string("jobs: ") + sqlite3_errmsg(db_));
  if (rc != SQLITE_DONE) throw IoError(std::string("jobs: ") + sqlite3_errmsg(db_));
}

void JobStore::put_all(const std::vector<std::shared_ptr<Job>>& jobs) {
  exec_sql(db_, "BEGIN", "jobs");
  try {
    for (const auto& j : jobs) put(*j);
  } catch (...) {
    exec_sql(db_, "ROLLBACK", "jobs");
    throw;
  }
  exec_sql(db_, "COMMIT", "jobs");
}

}  // namespace cgview::server
