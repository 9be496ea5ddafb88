#include "server/store/sqlite_mesh_store.h"

#include <fmt/format.h>
#include <sqlite3.h>

#include "core/mesh/subdivision_rules.h"
#include "server/store/store_schema.h"

namespace tessera::server {
namespace {

// Prepared statement with RAII finalisation; every failure becomes a StoreError with SQLite's
// own message.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql) : db_(db) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) fail("prepare");
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  void bind(int i, std::string_view text) {
    check(sqlite3_bind_text(stmt_, i, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT));
  }
  void bindBlob(int i, std::string_view bytes) {
    check(sqlite3_bind_blob64(stmt_, i, bytes.data(), bytes.size(), SQLITE_TRANSIENT));
  }
  void bind(int i, int64_t v) { check(sqlite3_bind_int64(stmt_, i, v)); }
  void bind(int i, double v) { check(sqlite3_bind_double(stmt_, i, v)); }

  // Returns true while there is a row to read.
  bool step() {
    int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail("step");
  }
  int64_t integer(int i) const { return sqlite3_column_int64(stmt_, i); }
  double real(int i) const { return sqlite3_column_double(stmt_, i); }
  std::string text(int i) const {
    auto p = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, i));
    return p ? std::string(p, sqlite3_column_bytes(stmt_, i)) : std::string();
  }
  std::string blob(int i) const {
    auto p = static_cast<const char*>(sqlite3_column_blob(stmt_, i));
    return p ? std::string(p, sqlite3_column_bytes(stmt_, i)) : std::string();
  }

 private:
  void check(int rc) {
    if (rc != SQLITE_OK) fail("bind");
  }
  [[noreturn]] void fail(const char* what) {
    throw StoreError(fmt::format("sqlite {}: {}", what, sqlite3_errmsg(db_)));
  }
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

MeshMetadata readMetadata(const Statement& s) {
  MeshMetadata m;
  m.id = s.text(0);
  m.displayName = s.text(1);
  m.sourceFormat = static_cast<SourceFormat>(s.integer(2));
  m.sourceBytes = s.integer(3);
  m.rules = rulesFromColumn(s.integer(4), m.id);
  m.vertexCount = s.integer(5);
  m.faceCount = s.integer(6);
  m.faceVertexCount = s.integer(7);
  m.creaseCount = s.integer(8);
  m.cornerCount = s.integer(9);
  m.holeCount = s.integer(10);
  m.boundsMin = Vec3d(s.real(11), s.real(12), s.real(13));
  m.boundsMax = Vec3d(s.real(14), s.real(15), s.real(16));
  m.sha256 = s.text(17);
  m.createTimeMicros = s.integer(18);
  m.storedBytes = s.integer(19);
  return m;
}

void bindMetadata(Statement& s, const MeshMetadata& m) {
  s.bind(1, m.id);
  s.bind(2, m.displayName);
  s.bind(3, static_cast<int64_t>(m.sourceFormat));
  s.bind(4, m.sourceBytes);
  s.bind(5, static_cast<int64_t>(rulesCode(m.rules)));
  s.bind(6, m.vertexCount);
  s.bind(7, m.faceCount);
  s.bind(8, m.faceVertexCount);
  s.bind(9, m.creaseCount);
  s.bind(10, m.cornerCount);
  s.bind(11, m.holeCount);
  s.bind(12, m.boundsMin.x), s.bind(13, m.boundsMin.y), s.bind(14, m.boundsMin.z);
  s.bind(15, m.boundsMax.x), s.bind(16, m.boundsMax.y), s.bind(17, m.boundsMax.z);
  s.bind(18, m.sha256);
  s.bind(19, m.createTimeMicros);
  s.bind(20, m.storedBytes);
}

// "?, ?, ..." for the metadata columns.
std::string placeholders() {
  std::string list = "?";
  for (int i = 1; i < schema::kMetadataColumnCount; ++i) list += ", ?";
  return list;
}

}  // namespace

SqliteMeshStore::SqliteMeshStore(const std::string& path) : path_(path) {
  int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX;
  if (sqlite3_open_v2(path.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
    std::string message = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    throw StoreError(fmt::format("cannot open SQLite store {}: {}", path, message));
  }
  try {
    sqlite3_busy_timeout(db_, 5000);
    exec("PRAGMA journal_mode=WAL");
    // FULL makes every commit wait for its WAL frame to be synced: the durability promise.
    exec("PRAGMA synchronous=FULL");
    createSchema();
  } catch (...) {
    sqlite3_close(db_);
    throw;
  }
}

SqliteMeshStore::~SqliteMeshStore() { sqlite3_close(db_); }

void SqliteMeshStore::exec(const char* sql) {
  char* error = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &error) != SQLITE_OK) {
    std::string message = error ? error : sqlite3_errmsg(db_);
    sqlite3_free(error);
    throw StoreError(fmt::format("SQLite store {}: {}", path_, message));
  }
}

void SqliteMeshStore::createSchema() {
  Statement version(db_, "PRAGMA user_version");
  version.step();
  int64_t found = version.integer(0);
  if (found > schema::kVersion) {
    throw StoreError(fmt::format("SQLite store {} has schema version {}, newer than this server's {}",
                                 path_, found, schema::kVersion));
  }
  exec(
      "CREATE TABLE IF NOT EXISTS meshes ("
      " id TEXT PRIMARY KEY, display_name TEXT NOT NULL, source_format INTEGER NOT NULL,"
      " source_bytes INTEGER NOT NULL, boundary INTEGER NOT NULL, vertex_count INTEGER NOT NULL,"
      " face_count INTEGER NOT NULL, face_vertex_count INTEGER NOT NULL,"
      " crease_count INTEGER NOT NULL, corner_count INTEGER NOT NULL,"
      " hole_count INTEGER NOT NULL, min_x REAL NOT NULL, min_y REAL NOT NULL,"
      " min_z REAL NOT NULL, max_x REAL NOT NULL, max_y REAL NOT NULL, max_z REAL NOT NULL,"
      " sha256 TEXT NOT NULL, create_time_us INTEGER NOT NULL, stored_bytes INTEGER NOT NULL,"
      " content BLOB NOT NULL)");
  exec(fmt::format("PRAGMA user_version={}", schema::kVersion).c_str());
}

bool SqliteMeshStore::insert(const MeshMetadata& metadata, std::string_view content) {
  std::lock_guard lock(mutex_);
  // OR IGNORE turns a taken id into "no row changed" instead of an error; the single statement
  // is its own transaction, committed (and synced) when step() returns.
  Statement s(db_, fmt::format("INSERT OR IGNORE INTO meshes ({}, content) VALUES ({}, ?)",
                               schema::kMetadataColumns, placeholders()));
  bindMetadata(s, metadata);
  s.bindBlob(schema::kMetadataColumnCount + 1, content);
  s.step();
  return sqlite3_changes(db_) == 1;
}

std::optional<MeshMetadata> SqliteMeshStore::findMetadata(std::string_view id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, fmt::format("SELECT {} FROM meshes WHERE id = ?", schema::kMetadataColumns));
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return readMetadata(s);
}

std::optional<StoredMesh> SqliteMeshStore::load(std::string_view id) {
  std::lock_guard lock(mutex_);
  Statement s(db_,
              fmt::format("SELECT {}, content FROM meshes WHERE id = ?", schema::kMetadataColumns));
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return StoredMesh{readMetadata(s), s.blob(schema::kMetadataColumnCount)};
}

std::vector<MeshMetadata> SqliteMeshStore::list(std::string_view afterId, int limit) {
  std::lock_guard lock(mutex_);
  Statement s(db_, fmt::format("SELECT {} FROM meshes WHERE id > ? ORDER BY id LIMIT ?",
                               schema::kMetadataColumns));
  s.bind(1, afterId);
  s.bind(2, static_cast<int64_t>(limit));
  std::vector<MeshMetadata> page;
  while (s.step()) page.push_back(readMetadata(s));
  return page;
}

bool SqliteMeshStore::remove(std::string_view id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "DELETE FROM meshes WHERE id = ?");
  s.bind(1, id);
  s.step();
  return sqlite3_changes(db_) == 1;
}

StoreStats SqliteMeshStore::stats() {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT count(*), coalesce(sum(stored_bytes), 0) FROM meshes");
  s.step();
  return StoreStats{s.integer(0), s.integer(1)};
}

void SqliteMeshStore::probe() {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT id FROM meshes ORDER BY id LIMIT 1");
  s.step();
}

}  // namespace tessera::server
