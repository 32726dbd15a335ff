// The server's store: mesh metadata in SQLite, mesh files as blobs on disk,
// both under one data directory:
//   DATA/cgview.db            SQLite (WAL): one row per mesh
//   DATA/blobs/ID.EXT         the uploaded bytes, as uploaded
//   DATA/blobs/ID.texN        the mesh's texture images (N = 0, 1, ...), if any
// and the users: their tokens (hashed) and what is shared with whom.
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
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "mesh_json.h"

struct sqlite3;

namespace cgview::server {

// Who asks: a user and whether they may see everything.
struct Caller {
  Caller() = default;
  Caller(std::string user_, bool admin_ = false, bool teacher_ = false)
      : user(std::move(user_)), admin(admin_), teacher(teacher_) {}
  std::string user = "local";
  bool admin = false;
  bool teacher = false;  // may create courses (server/teaching/courses.h)
  // The groups the user is in, read at each request: "course:ID" for a
  // course's members, "staff:ID" for its teachers and assistants.  An item
  // shared with a group is read by its members.
  std::vector<std::string> groups;
  // The single user of a server that needs no token: it sees everything.
  static Caller local() { return {"local", true, true}; }
  bool in(const std::string& group) const;
};

// Who may read a mesh or a job: its owner, the users it was shared with, or
// everyone; admins read everything.
struct Access {
  Access(std::string owner_ = {}, std::vector<std::string> readers_ = {})
      : owner(std::move(owner_)), readers(std::move(readers_)) {}
  std::string owner;
  std::vector<std::string> readers;
  bool everyone = false;
  bool allows(const Caller& c) const;
  // Reads and also changes (delete, share): the owner or an admin.
  bool owned_by(const Caller& c) const { return c.admin || c.user == owner; }
};

// A 403: the caller reads the item (it was shared with them) but may not change it.
struct Forbidden : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The owner of the sample meshes loaded at start (shared with everyone).
inline constexpr const char* kSystemOwner = "system";
// The user name that means "everyone" in a share.
inline constexpr const char* kEveryone = "*";

struct UserRecord {
  std::string name;
  bool admin = false;
  std::string created;
  int tokens = 0;        // live tokens
  bool teacher = false;  // may create courses
  std::string role() const { return admin ? "admin" : teacher ? "teacher" : "user"; }
};

// A stored mesh's record: its shape is the protocol's (protocol/mesh_json.h).
using protocol::MeshRecord;

class Store {
 public:
  // Opens (creating if needed) the store in data_dir; throws IoError.
  explicit Store(const std::filesystem::path& data_dir);
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  // Saves the bytes, the texture images (blobs of the mesh, written before
  // its row) and the record; assigns id and created.
  MeshRecord add_mesh(MeshRecord record, std::string_view bytes, const std::vector<std::string>& textures = {});
  // The meshes the caller may read, oldest first.
  std::vector<MeshRecord> list_meshes(const Caller& caller = Caller::local()) const;
  // The mesh if the caller may read it; nullopt also when it exists but is
  // another user's (the two answer alike).
  std::optional<MeshRecord> get_mesh(const std::string& id, const Caller& caller = Caller::local()) const;
  // The oldest mesh with these bytes that `owner` owns.
  std::optional<MeshRecord> find_by_sha256(const std::string& sha256, const std::string& owner = "local") const;
  // False when there was no such mesh.
  bool remove_mesh(const std::string& id);
  // The uploaded bytes of a mesh; throws IoError when the blob is missing.
  std::string read_blob(const MeshRecord& record) const;
  // The bytes of a mesh's texture n; throws std::out_of_range when it has none such.
  std::string read_texture(const MeshRecord& record, std::size_t n) const;
  // A mesh's cached preview (DATA/blobs/ID.preview.drc, a blob of the mesh,
  // removed with it): nullopt when none was written.  write_preview does
  // nothing when the mesh's file is gone (deleted meanwhile).
  std::optional<std::string> read_preview(const MeshRecord& record) const;
  void write_preview(const MeshRecord& record, std::string_view bytes) const;
  // The path of a mesh's stored file (for a worker process to read).
  std::filesystem::path blob_file(const MeshRecord& record) const { return blob_path(record); }
  std::size_t count() const { return count_; }
  // How many meshes the caller may read (list_meshes(caller).size(), by one
  // COUNT query; an admin's is count()).
  std::size_t count(const Caller& caller) const;
  // The bytes of the meshes `owner` owns, files and texture images (their quota counts them).
  std::uint64_t mesh_bytes(const std::string& owner) const;
  // The same, of every owner.
  std::uint64_t total_bytes() const;

  // Shares an item with users (by name, or kEveryone), or stops sharing it
  // (shared false); kind is "mesh" or "job".
  void set_shared(const std::string& kind, const std::string& id, const std::vector<std::string>& users, bool shared);
  // The users an item is shared with (kEveryone included as such).
  std::vector<std::string> shared_with(const std::string& kind, const std::string& id) const;
  // Who reads an item of that owner: the owner and what it is shared with.
  Access access(const std::string& kind, const std::string& id, std::string owner) const;
  // A mesh's owner and readers; nullopt when there is no such mesh.
  std::optional<Access> mesh_access(const std::string& id) const;

  // Users and their tokens.  add_user creates the user or changes their role
  // (admin, teacher); ensure_user creates one that is missing, with no role,
  // and says whether it did.
  void add_user(const std::string& name, bool admin, bool teacher = false);
  bool ensure_user(const std::string& name);
  std::optional<UserRecord> get_user(const std::string& name) const;
  std::vector<UserRecord> list_users() const;
  // token_id: the public part of a token; hash: the SHA-256 of its secret.
  void add_token(const std::string& token_id, const std::string& user, const std::string& hash);
  // The user and hash of a token id.
  std::optional<std::pair<std::string, std::string>> find_token(const std::string& token_id) const;
  // Deletes every token of a user; how many there were.
  int revoke_tokens(const std::string& user);
  // A number that changes whenever the database may have changed under a
  // caller's authentication: a commit by another connection (SQLite's
  // data_version: the CLI's `user revoke`, the courses' members) or a
  // change of users or tokens through this one.  Cheap: no query of a table.
  std::int64_t version() const;
  const std::filesystem::path& data_dir() const { return dir_; }

 private:
  std::filesystem::path blob_path(const MeshRecord& r) const;
  std::filesystem::path texture_path(const std::string& id, std::size_t n) const;
  std::filesystem::path preview_path(const MeshRecord& r) const;
  void remove_blobs(const MeshRecord& r) const;  // the mesh's file and its textures
  std::filesystem::path dir_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
  std::atomic<std::size_t> count_{0};         // rows, kept by add and remove (health asks it often)
  std::atomic<std::int64_t> own_changes_{0};  // users and tokens changed through this connection
};

// Lowercase hex SHA-256 of bytes.
std::string sha256_hex(std::string_view bytes);
// Lowercase hex of n bytes.
std::string to_hex(const unsigned char* bytes, std::size_t n);
// A new random id: 16 hex digits.
std::string new_id();
// The current time, ISO 8601 UTC ("2026-11-21T12:00:00Z").
std::string now_iso8601();
// Opens (creating) the SQLite database at path in WAL mode with a busy
// timeout, for the store and the job scheduler alike; throws IoError.
sqlite3* open_database(const std::filesystem::path& path);
// Runs SQL statements; throws IoError("WHO: message") on failure.
void exec_sql(sqlite3* db, const char* sql, const char* who);
// Adds a column that a database from an older version lacks (DECL: "TEXT
// NOT NULL DEFAULT 'x'"); throws IoError.
void add_missing_column(sqlite3* db, const char* table, const char* column, const char* decl, const char* who);

}  // namespace cgview::server
