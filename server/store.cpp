#include "store.h"

#include <openssl/evp.h>
#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "sqlite_stmt.h"

namespace cgview::server {

namespace fs = std::filesystem;

namespace {

constexpr const char* kColumns = "id, name, format, bytes, sha256, created, report, warnings, owner, material";
// The meshes caller ?1 (admin: ?2, groups: the JSON array ?9) may read.
constexpr const char* kReadable =
    "(?2 OR owner = ?1 OR id IN (SELECT item FROM shares WHERE kind = 'mesh' AND (user = ?1 OR user = '*'"
    " OR user IN (SELECT value FROM json_each(?9)))))";

// A caller's groups as the JSON array that kReadable's json_each reads.
std::string groups_json(const Caller& c) { return nlohmann::json(c.groups).dump(); }

MeshRecord row(const Stmt& s) {
  return {s.text(0), s.text(1), s.text(2), std::uint64_t(s.integer(3)), s.text(4), s.text(5), s.text(6),
          s.text(7), s.text(8), s.text(9)};
}

std::string mesh_query(const std::string& where) {
  return std::string("SELECT ") + kColumns + " FROM meshes WHERE " + kReadable + where;
}

bool safe_ext(const std::string& f) {
  if (f.empty() || f.size() > 8) return false;
  for (char c : f)
    if (!std::isalnum(static_cast<unsigned char>(c))) return false;
  return true;
}

}  // namespace

std::string new_id() {
  static std::mutex m;
  static std::mt19937_64 rng{std::random_device{}()};
  std::lock_guard lock(m);
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(rng()));
  return buf;
}

std::string now_iso8601() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

sqlite3* open_database(const fs::path& path) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX, nullptr) !=
      SQLITE_OK) {
    std::string msg = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw IoError(path.string() + ": cannot open: " + msg);
  }
  sqlite3_busy_timeout(db, 5000);
  try {
    exec_sql(db, "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;", path.string().c_str());
  } catch (...) {
    sqlite3_close(db);
    throw;
  }
  return db;
}

void exec_sql(sqlite3* db, const char* sql, const char* who) {
  char* err = nullptr;
  if (const int rc = sqlite3_exec(db, sql, nullptr, nullptr, &err); rc != SQLITE_OK) {
    std::string msg = err ? err : "unknown error";
    sqlite3_free(err);
    if (rc == SQLITE_FULL) throw DiskFull(std::string(who) + ": " + msg);
    throw IoError(std::string(who) + ": " + msg);
  }
}

void add_missing_column(sqlite3* db, const char* table, const char* column, const char* decl, const char* who) {
  sqlite3_stmt* probe = nullptr;
  const std::string select = std::string("SELECT ") + column + " FROM " + table + " LIMIT 0";
  const bool has = sqlite3_prepare_v2(db, select.c_str(), -1, &probe, nullptr) == SQLITE_OK;
  sqlite3_finalize(probe);
  if (!has)
    exec_sql(db, (std::string("ALTER TABLE ") + table + " ADD COLUMN " + column + " " + decl + ";").c_str(), who);
}

bool Caller::in(const std::string& group) const {
  return std::find(groups.begin(), groups.end(), group) != groups.end();
}

bool Access::allows(const Caller& c) const {
  if (owned_by(c) || everyone) return true;
  for (const std::string& r : readers)
    if (r == c.user || c.in(r)) return true;
  return false;
}

std::string sha256_hex(std::string_view bytes) {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  if (!EVP_Digest(bytes.data(), bytes.size(), md, &n, EVP_sha256(), nullptr)) throw Error("SHA-256 failed");
  return to_hex(md, n);
}

std::string to_hex(const unsigned char* bytes, std::size_t n) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  out.reserve(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    out.push_back(hex[bytes[i] >> 4]);
    out.push_back(hex[bytes[i] & 15]);
  }
  return out;
}

Store::Store(const fs::path& data_dir) : dir_(data_dir) {
  std::error_code ec;
  fs::create_directories(dir_ / "blobs", ec);
  if (ec) throw IoError(dir_.string() + ": cannot create the data directory: " + ec.message());
  db_ = open_database(dir_ / "cgview.db");
  exec_sql(db_, "PRAGMA foreign_keys=ON;", "store");
  exec_sql(db_,
           "CREATE TABLE IF NOT EXISTS meshes ("
           " id TEXT PRIMARY KEY, name TEXT NOT NULL, format TEXT NOT NULL, bytes INTEGER NOT NULL,"
           " sha256 TEXT NOT NULL, created TEXT NOT NULL, report TEXT NOT NULL, warnings TEXT NOT NULL,"
           " seq INTEGER);"
           "CREATE INDEX IF NOT EXISTS meshes_sha ON meshes(sha256);"
           "CREATE TABLE IF NOT EXISTS users (name TEXT PRIMARY KEY, admin INTEGER NOT NULL, created TEXT NOT NULL);"
           "CREATE TABLE IF NOT EXISTS tokens (id TEXT PRIMARY KEY, user TEXT NOT NULL, hash TEXT NOT NULL, created "
           "TEXT NOT NULL);"
           "CREATE TABLE IF NOT EXISTS shares (kind TEXT NOT NULL, item TEXT NOT NULL, user TEXT NOT NULL,"
           " PRIMARY KEY (kind, item, user));",
           "store");
  // Meshes stored before users belong to the local user.
  add_missing_column(db_, "meshes", "owner", "TEXT NOT NULL DEFAULT 'local'", "store");
  add_missing_column(db_, "meshes", "material", "TEXT NOT NULL DEFAULT '{}'", "store");
  add_missing_column(db_, "users", "teacher", "INTEGER NOT NULL DEFAULT 0", "store");
  {
    Stmt s(db_, "SELECT COUNT(*) FROM meshes");
    s.step();
    count_ = std::size_t(s.integer(0));
  }
  // A crash while a blob is written leaves its .part file; one between the
  // blob's write and its row's insert, a blob no record names.  Neither was
  // ever seen by a user, and neither is kept.
  std::set<std::string> ids;
  {
    Stmt s(db_, "SELECT id FROM meshes");
    while (s.step()) ids.insert(s.text(0));
  }
  std::vector<fs::path> orphans;
  for (const auto& e : fs::directory_iterator(dir_ / "blobs", ec)) {
    const std::string name = e.path().filename().string();
    if (e.path().extension() == ".part" || !ids.count(name.substr(0, name.find('.')))) orphans.push_back(e.path());
  }
  for (const fs::path& p : orphans) fs::remove(p, ec);
}

Store::~Store() { sqlite3_close(db_); }

fs::path Store::blob_path(const MeshRecord& r) const { return dir_ / "blobs" / (r.id + "." + r.format); }

namespace {
// A blob's whole bytes, or none when the file is not there.
std::optional<std::string> read_whole(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return std::nullopt;
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}
}  // namespace

fs::path Store::texture_path(const std::string& id, std::size_t n) const {
  return dir_ / "blobs" / (id + ".tex" + std::to_string(n));
}

void Store::remove_blobs(const MeshRecord& r) const {
  std::error_code ec;
  fs::remove(blob_path(r), ec);
  fs::remove(preview_path(r), ec);
  for (std::size_t n = 0; fs::remove(texture_path(r.id, n), ec); ++n) {
  }
}

fs::path Store::preview_path(const MeshRecord& r) const { return dir_ / "blobs" / (r.id + ".preview.drc"); }

std::optional<std::string> Store::read_preview(const MeshRecord& r) const { return read_whole(preview_path(r)); }

void Store::write_preview(const MeshRecord& r, std::string_view bytes) const {
  std::error_code ec;
  if (fs::exists(blob_path(r), ec)) write_file_bytes(preview_path(r), bytes);
}

MeshRecord Store::add_mesh(MeshRecord r, std::string_view bytes, const std::vector<std::string>& textures) {
  if (!safe_ext(r.format)) throw InvalidInput("bad format name '" + r.format + "'");
  r.id = new_id();
  r.created = now_iso8601();
  r.bytes = bytes.size();
  try {
    for (std::size_t n = 0; n < textures.size(); ++n) write_file_bytes(texture_path(r.id, n), textures[n]);
    write_file_bytes(blob_path(r), bytes);
  } catch (...) {
    remove_blobs(r);
    throw;
  }
  std::lock_guard lock(mutex_);
  try {
    Stmt s(db_,
           "INSERT INTO meshes (id, name, format, bytes, sha256, created, report, warnings, owner, material, seq)"
           " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, (SELECT IFNULL(MAX(seq), 0) + 1 FROM meshes))");
    s.bind(1, r.id).bind(2, r.name).bind(3, r.format).bind(4, std::int64_t(r.bytes)).bind(5, r.sha256);
    s.bind(6, r.created).bind(7, r.report_json).bind(8, r.warnings_json).bind(9, r.owner).bind(10, r.material_json);
    s.step();
    ++count_;
  } catch (...) {
    remove_blobs(r);
    throw;
  }
  return r;
}

std::vector<MeshRecord> Store::list_meshes(const Caller& caller) const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, mesh_query(" ORDER BY seq").c_str());
  s.bind(1, caller.user).bind(2, std::int64_t(caller.admin)).bind(9, groups_json(caller));
  std::vector<MeshRecord> out;
  while (s.step()) out.push_back(row(s));
  return out;
}

std::size_t Store::count(const Caller& caller) const {
  if (caller.admin) return count_;
  std::lock_guard lock(mutex_);
  Stmt s(db_, (std::string("SELECT COUNT(*) FROM meshes WHERE ") + kReadable).c_str());
  s.bind(1, caller.user).bind(2, std::int64_t(caller.admin)).bind(9, groups_json(caller));
  return s.step() ? std::size_t(s.integer(0)) : 0;
}

namespace {
// The mesh file and its texture images (blobs of the mesh, sized in its material).
constexpr const char* kMeshBytesSql =
    "SELECT IFNULL(SUM(bytes + IFNULL((SELECT SUM(json_extract(t.value, '$.bytes'))"
    " FROM json_each(material, '$.textures') AS t), 0)), 0) FROM meshes";
}  // namespace

std::uint64_t Store::mesh_bytes(const std::string& owner) const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, (std::string(kMeshBytesSql) + " WHERE owner = ?1").c_str());
  s.bind(1, owner);
  return s.step() ? std::uint64_t(s.integer(0)) : 0;
}

std::uint64_t Store::total_bytes() const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, kMeshBytesSql);
  return s.step() ? std::uint64_t(s.integer(0)) : 0;
}

std::optional<MeshRecord> Store::get_mesh(const std::string& id, const Caller& caller) const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, mesh_query(" AND id = ?3").c_str());
  s.bind(1, caller.user).bind(2, std::int64_t(caller.admin)).bind(3, id).bind(9, groups_json(caller));
  if (!s.step()) return std::nullopt;
  return row(s);
}

std::optional<MeshRecord> Store::find_by_sha256(const std::string& sha, const std::string& owner) const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, (std::string("SELECT ") + kColumns + " FROM meshes WHERE sha256 = ?1 AND owner = ?2 ORDER BY seq LIMIT 1")
                  .c_str());
  s.bind(1, sha).bind(2, owner);
  if (!s.step()) return std::nullopt;
  return row(s);
}

bool Store::remove_mesh(const std::string& id) {
  std::optional<MeshRecord> r = get_mesh(id);
  if (!r) return false;
  {
    std::lock_guard lock(mutex_);
    Stmt s(db_, "DELETE FROM meshes WHERE id = ?1");
    s.bind(1, id);
    s.step();
    if (sqlite3_changes(db_) == 0) return false;
    --count_;
    Stmt shares(db_, "DELETE FROM shares WHERE kind = 'mesh' AND item = ?1");
    shares.bind(1, id);
    shares.step();
  }
  remove_blobs(*r);
  return true;
}

std::string Store::read_blob(const MeshRecord& r) const {
  std::ifstream f(blob_path(r), std::ios::binary);
  if (!f) throw IoError("store: the file of mesh " + r.id + " is missing");
  std::string bytes(r.bytes, '\0');
  f.read(bytes.data(), std::streamsize(bytes.size()));
  if (std::uint64_t(f.gcount()) != r.bytes) throw IoError("store: the file of mesh " + r.id + " is truncated");
  return bytes;
}

std::string Store::read_texture(const MeshRecord& r, std::size_t n) const {
  std::optional<std::string> bytes = read_whole(texture_path(r.id, n));
  if (!bytes) throw std::out_of_range("mesh " + r.id + " has no texture " + std::to_string(n));
  return std::move(*bytes);
}

void Store::set_shared(const std::string& kind, const std::string& id, const std::vector<std::string>& users,
                       bool shared) {
  std::lock_guard lock(mutex_);
  for (const auto& u : users) {
    Stmt s(db_, shared ? "INSERT OR IGNORE INTO shares (kind, item, user) VALUES (?1, ?2, ?3)"
                       : "DELETE FROM shares WHERE kind = ?1 AND item = ?2 AND user = ?3");
    s.bind(1, kind).bind(2, id).bind(3, u);
    s.step();
  }
}

std::vector<std::string> Store::shared_with(const std::string& kind, const std::string& id) const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, "SELECT user FROM shares WHERE kind = ?1 AND item = ?2 ORDER BY user");
  s.bind(1, kind).bind(2, id);
  std::vector<std::string> out;
  while (s.step()) out.push_back(s.text(0));
  return out;
}

Access Store::access(const std::string& kind, const std::string& id, std::string owner) const {
  Access a{std::move(owner), shared_with(kind, id)};
  const auto all = std::find(a.readers.begin(), a.readers.end(), kEveryone);
  a.everyone = all != a.readers.end();
  if (a.everyone) a.readers.erase(all);
  return a;
}

std::optional<Access> Store::mesh_access(const std::string& id) const {
  const auto rec = get_mesh(id);
  if (!rec) return std::nullopt;
  return access("mesh", id, rec->owner);
}

void Store::add_user(const std::string& name, bool admin, bool teacher) {
  ++own_changes_;
  std::lock_guard lock(mutex_);
  Stmt s(db_,
         "INSERT INTO users (name, admin, created, teacher) VALUES (?1, ?2, ?3, ?4)"
         " ON CONFLICT(name) DO UPDATE SET admin = excluded.admin, teacher = excluded.teacher");
  s.bind(1, name).bind(2, std::int64_t(admin)).bind(3, now_iso8601()).bind(4, std::int64_t(teacher));
  s.step();
}

bool Store::ensure_user(const std::string& name) {
  std::lock_guard lock(mutex_);
  Stmt s(db_, "INSERT OR IGNORE INTO users (name, admin, created) VALUES (?1, 0, ?2)");
  s.bind(1, name).bind(2, now_iso8601());
  s.step();
  return sqlite3_changes(db_) > 0;
}

namespace {
constexpr const char* kUserQuery =
    "SELECT name, admin, created, (SELECT COUNT(*) FROM tokens WHERE tokens.user = users.name), teacher FROM users";
UserRecord user_row(const Stmt& s) {
  return {s.text(0), s.integer(1) != 0, s.text(2), int(s.integer(3)), s.integer(4) != 0};
}
}  // namespace

std::optional<UserRecord> Store::get_user(const std::string& name) const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, (std::string(kUserQuery) + " WHERE name = ?1").c_str());
  s.bind(1, name);
  if (!s.step()) return std::nullopt;
  return user_row(s);
}

std::vector<UserRecord> Store::list_users() const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, (std::string(kUserQuery) + " ORDER BY name").c_str());
  std::vector<UserRecord> out;
  while (s.step()) out.push_back(user_row(s));
  return out;
}

void Store::add_token(const std::string& token_id, const std::string& user, const std::string& hash) {
  std::lock_guard lock(mutex_);
  Stmt s(db_, "INSERT INTO tokens (id, user, hash, created) VALUES (?1, ?2, ?3, ?4)");
  s.bind(1, token_id).bind(2, user).bind(3, hash).bind(4, now_iso8601());
  s.step();
}

std::optional<std::pair<std::string, std::string>> Store::find_token(const std::string& token_id) const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, "SELECT user, hash FROM tokens WHERE id = ?1");
  s.bind(1, token_id);
  if (!s.step()) return std::nullopt;
  return std::pair{s.text(0), s.text(1)};
}

std::int64_t Store::version() const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, "PRAGMA data_version");
  const std::int64_t v = s.step() ? s.integer(0) : 0;
  return (v << 24) + own_changes_.load();
}

int Store::revoke_tokens(const std::string& user) {
  ++own_changes_;
  std::lock_guard lock(mutex_);
  Stmt s(db_, "DELETE FROM tokens WHERE user = ?1");
  s.bind(1, user);
  s.step();
  return sqlite3_changes(db_);
}

}  // namespace cgview::server
