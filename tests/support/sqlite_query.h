// Runs one SQL statement on a database file (the server stopped): for
// checking what the server stored, and for making old databases.
#pragma once

#include <sqlite3.h>

#include <filesystem>
#include <string>

namespace cgview::test {

// The first column of the statement's last row ("" when it returns none,
// "NULL" for a null), or "error: ..." / "cannot open".
inline std::string sqlite_query(const std::filesystem::path& db_path, const std::string& statement) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    sqlite3_close(db);  // a handle is made even when opening fails
    return "cannot open";
  }
  std::string result;
  char* err = nullptr;
  sqlite3_exec(
      db, statement.c_str(),
      [](void* out, int, char** values, char**) {
        *static_cast<std::string*>(out) = values[0] ? values[0] : "NULL";
        return 0;
      },
      &result, &err);
  if (err) result = std::string("error: ") + err;
  sqlite3_free(err);
  sqlite3_close(db);
  return result;
}

// SQLite's own check of a database file: "ok" when sound.
inline std::string integrity_check(const std::filesystem::path& db_path) {
  return sqlite_query(db_path, "PRAGMA integrity_check");
}

}  // namespace cgview::test
