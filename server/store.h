// The server's store: mesh metadata in SQLite, mesh files as blobs on disk,
// both under one data directory:
//   DATA/cgview.db            SQLite (WAL): one row per mesh
//   DATA/blobs/ID.EXT         the uploaded bytes, as uploaded
// A blob is written (to a temporary name, then renamed) before its row is
// committed, and removed after its row is deleted, so a crash at any point
// leaves no row without its file.  Thread-safe.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

struct sqlite3;

namespace cgview::server {

struct MeshRecord {
  std::string id;       // 16 hex digits
  std::string name;     // as uploaded ("elephant.off")
  std::string format;   // "off", "ply", ...
  std::uint64_t bytes = 0;
  std::string sha256;   // of the uploaded bytes
  std::string created;  // ISO 8601 UTC
  std::string report_json;    // protocol::to_json(MeshReport), serialized
  std::string warnings_json;  // JSON array of strings
};

class Store {
 public:
  // Opens (creating if needed) the store in data_dir; throws IoError.
  explicit Store(const std::filesystem::path& data_dir);
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  // Saves the bytes and the record; assigns id and created.
  MeshRecord add_mesh(MeshRecord record, std::string_view bytes);
  std::vector<MeshRecord> list_meshes() const;
  std::optional<MeshRecord> get_mesh(const std::string& id) const;
  std::optional<MeshRecord> find_by_sha256(const std::string& sha256) const;
  // False when there was no such mesh.
  bool remove_mesh(const std::string& id);
  // The uploaded bytes of a mesh; throws IoError when the blob is missing.
  std::string read_blob(const MeshRecord& record) const;
  // The path of a mesh's stored file (for a worker process to read).
  std::filesystem::path blob_file(const MeshRecord& record) const { return blob_path(record); }
  std::size_t count() const { return count_; }
  const std::filesystem::path& data_dir() const { return dir_; }

 private:
  std::filesystem::path blob_path(const MeshRecord& r) const;
  std::filesystem::path dir_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
  std::atomic<std::size_t> count_{0};  // rows, kept by add and remove (health asks it often)
};

// Lowercase hex SHA-256 of bytes.
std::string sha256_hex(std::string_view bytes);
// A new random id: 16 hex digits.
std::string new_id();
// The current time, ISO 8601 UTC ("2026-11-21T12:00:00Z").
std::string now_iso8601();
// Opens (creating) the SQLite database at path in WAL mode with a busy
// timeout, for the store and the job scheduler alike; throws IoError.
sqlite3* open_database(const std::filesystem::path& path);
// Runs SQL statements; throws IoError("WHO: message") on failure.
void exec_sql(sqlite3* db, const char* sql, const char* who);

}  // namespace cgview::server
