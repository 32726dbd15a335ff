// Jobs in the store's SQLite database (table jobs), one row each: loaded
// whole at start, written one job at a time as it changes.
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "jobs/job.h"

struct sqlite3;

namespace cgview::server {

class JobStore {
 public:
  // Opens (creating or migrating) the table in DATA/cgview.db.
  explicit JobStore(const std::filesystem::path& data_dir);
  ~JobStore();
  JobStore(const JobStore&) = delete;
  JobStore& operator=(const JobStore&) = delete;

  // Every job, oldest first.
  std::vector<std::shared_ptr<Job>> load() const;
  // Inserts or replaces the job's row; throws DiskFull or IoError.
  void put(const Job& job);
  // Several puts in one transaction (all or none).
  void put_all(const std::vector<std::shared_ptr<Job>>& jobs);
  // Forgets a job (throws IoError, DiskFull).
  void remove(const std::string& id);

 private:
  sqlite3* db_ = nullptr;
};

}  // namespace cgview::server
