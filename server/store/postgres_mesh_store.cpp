#include "server/store/postgres_mesh_store.h"

#include <fmt/format.h>
#include <libpq-fe.h>

#include <poll.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <utility>

#include "core/mesh/subdivision_rules.h"
#include "server/store/store_schema.h"

namespace tessera::server {
namespace {

// Arbitrary constant naming the advisory lock that serialises schema creation when several
// replicas start at once (CREATE TABLE IF NOT EXISTS alone can race in PostgreSQL).
constexpr int64_t kSchemaLockKey = 0x7e55e7a;

using ResultPtr = std::unique_ptr<PGresult, decltype(&PQclear)>;

// Parameters as libpq wants them: text values, except those marked binary (bytea content).
class Params {
 public:
  void text(std::string value) { add(std::move(value), 0); }
  void binary(std::string_view value) { add(std::string(value), 1); }
  void integer(int64_t v) { text(std::to_string(v)); }
  void real(double v) { text(fmt::format("{}", v)); }

  int size() const { return static_cast<int>(values_.size()); }
  std::vector<const char*> pointers() const {
    std::vector<const char*> p;
    for (const std::string& v : values_) p.push_back(v.data());
    return p;
  }
  std::vector<int> lengths() const {
    std::vector<int> l;
    for (const std::string& v : values_) l.push_back(static_cast<int>(v.size()));
    return l;
  }
  const std::vector<int>& formats() const { return formats_; }

 private:
  void add(std::string value, int format) {
    values_.push_back(std::move(value));
    formats_.push_back(format);
  }
  std::vector<std::string> values_;
  std::vector<int> formats_;
};

[[noreturn]] void fail(PGconn* c, const char* what) {
  std::string message = PQerrorMessage(c);
  while (!message.empty() && message.back() == '\n') message.pop_back();
  throw StoreError(fmt::format("postgresql: {}: {}", what, message));
}

// Waits until the connection's socket is ready for `events`, or the store's timeout passes with
// nothing: a frozen database (a stopped backend, a network dropping everything) must not hold the
// calling thread, and the client's call, without end. The connection is left mid-statement, so
// release() drops it.
void await(PGconn* c, short events, std::chrono::milliseconds timeout) {
  pollfd fd{PQsocket(c), events, 0};
  const int ready = ::poll(&fd, 1, int(timeout.count()));
  if (ready == 0) throw StoreError(fmt::format("postgresql: no answer within {} ms", timeout.count()));
  if (ready < 0 && errno != EINTR) throw StoreError("postgresql: poll failed");
}

// One statement, sent and answered without blocking past `timeout` of silence at any step.
ResultPtr execute(PGconn* c, const std::string& sql, const Params& params, std::chrono::milliseconds timeout) {
  auto values = params.pointers();
  auto lengths = params.lengths();
  if (!PQsendQueryParams(c, sql.c_str(), params.size(), nullptr, values.data(), lengths.data(),
                         params.formats().data(), 0)) {
    fail(c, "cannot send a statement");
  }
  for (int pending; (pending = PQflush(c)) != 0;) {
    if (pending < 0) fail(c, "cannot send a statement");
    await(c, POLLOUT | POLLIN, timeout);
    if (!PQconsumeInput(c)) fail(c, "connection lost");
  }
  ResultPtr result(nullptr, &PQclear);
  for (;;) {
    while (PQisBusy(c)) {
      await(c, POLLIN, timeout);
      if (!PQconsumeInput(c)) fail(c, "connection lost");
    }
    PGresult* next = PQgetResult(c);
    if (!next) break;
    result.reset(next);
  }
  ExecStatusType status = result ? PQresultStatus(result.get()) : PGRES_FATAL_ERROR;
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) {
    std::string message = result ? PQresultErrorMessage(result.get()) : PQerrorMessage(c);
    while (!message.empty() && message.back() == '\n') message.pop_back();
    throw StoreError("postgresql: " + message);
  }
  return result;
}

int64_t integerAt(const PGresult* r, int row, int col) {
  return std::strtoll(PQgetvalue(r, row, col), nullptr, 10);
}
double realAt(const PGresult* r, int row, int col) {
  return std::strtod(PQgetvalue(r, row, col), nullptr);
}
std::string textAt(const PGresult* r, int row, int col) {
  return std::string(PQgetvalue(r, row, col), PQgetlength(r, row, col));
}

MeshMetadata readMetadata(const PGresult* r, int row) {
  MeshMetadata m;
  m.id = textAt(r, row, 0);
  m.displayName = textAt(r, row, 1);
  m.sourceFormat = static_cast<SourceFormat>(integerAt(r, row, 2));
  m.sourceBytes = integerAt(r, row, 3);
  m.rules = rulesFromColumn(integerAt(r, row, 4), m.id);
  m.vertexCount = integerAt(r, row, 5);
  m.faceCount = integerAt(r, row, 6);
  m.faceVertexCount = integerAt(r, row, 7);
  m.creaseCount = integerAt(r, row, 8);
  m.cornerCount = integerAt(r, row, 9);
  m.holeCount = integerAt(r, row, 10);
  m.boundsMin = Vec3d(realAt(r, row, 11), realAt(r, row, 12), realAt(r, row, 13));
  m.boundsMax = Vec3d(realAt(r, row, 14), realAt(r, row, 15), realAt(r, row, 16));
  m.sha256 = textAt(r, row, 17);
  m.createTimeMicros = integerAt(r, row, 18);
  m.storedBytes = integerAt(r, row, 19);
  return m;
}

Params metadataParams(const MeshMetadata& m) {
  Params p;
  p.text(m.id);
  p.text(m.displayName);
  p.integer(static_cast<int64_t>(m.sourceFormat));
  p.integer(m.sourceBytes);
  p.integer(rulesCode(m.rules));
  p.integer(m.vertexCount), p.integer(m.faceCount), p.integer(m.faceVertexCount);
  p.integer(m.creaseCount), p.integer(m.cornerCount), p.integer(m.holeCount);
  p.real(m.boundsMin.x), p.real(m.boundsMin.y), p.real(m.boundsMin.z);
  p.real(m.boundsMax.x), p.real(m.boundsMax.y), p.real(m.boundsMax.z);
  p.text(m.sha256);
  p.integer(m.createTimeMicros);
  p.integer(m.storedBytes);
  return p;
}

std::string bytea(const PGresult* r, int row, int col) {
  size_t length = 0;
  auto raw = reinterpret_cast<const unsigned char*>(PQgetvalue(r, row, col));
  unsigned char* decoded = PQunescapeBytea(raw, &length);
  if (!decoded) throw StoreError("postgresql: cannot decode mesh content");
  std::string content(reinterpret_cast<const char*>(decoded), length);
  PQfreemem(decoded);
  return content;
}

}  // namespace

// A connection borrowed from the pool; returned (or dropped, if it broke) when destroyed.
class PostgresMeshStore::Lease {
 public:
  Lease(PostgresMeshStore& store, PGconn* c) : store_(&store), c_(c) {}
  Lease(Lease&& other) noexcept : store_(other.store_), c_(std::exchange(other.c_, nullptr)) {}
  ~Lease() {
    if (c_) store_->release(c_);
  }
  PGconn* get() const { return c_; }
  // One statement on this connection, within the store's timeout.
  ResultPtr run(const std::string& sql, const Params& params = {}) const {
    return execute(c_, sql, params, store_->timeout_);
  }

 private:
  PostgresMeshStore* store_;
  PGconn* c_;
};

PostgresMeshStore::PostgresMeshStore(std::string conninfo, std::chrono::milliseconds timeout, int poolSize)
    : conninfo_(std::move(conninfo)), timeout_(timeout), poolSize_(static_cast<size_t>(std::max(poolSize, 1))) {
  createSchema();
}

PostgresMeshStore::~PostgresMeshStore() {
  for (PGconn* c : idle_) PQfinish(c);
}

PGconn* PostgresMeshStore::connect() {
  // The URI first, then a connect timeout (whole seconds, at least 2: libpq's own floor) that a
  // frozen database cannot stretch.
  const std::string seconds = std::to_string(std::max<int64_t>(2, (timeout_.count() + 999) / 1000));
  const char* keywords[] = {"dbname", "connect_timeout", nullptr};
  const char* values[] = {conninfo_.c_str(), seconds.c_str(), nullptr};
  PGconn* c = PQconnectdbParams(keywords, values, /*expand_dbname=*/1);
  if (PQstatus(c) == CONNECTION_OK && PQsetnonblocking(c, 1) != 0) {
    PQfinish(c);
    throw StoreError("cannot connect to PostgreSQL store: cannot make the connection non-blocking");
  }
  if (PQstatus(c) != CONNECTION_OK) {
    std::string message = c ? PQerrorMessage(c) : "out of memory";
    while (!message.empty() && message.back() == '\n') message.pop_back();
    PQfinish(c);
    throw StoreError("cannot connect to PostgreSQL store: " + message);
  }
  return c;
}

PostgresMeshStore::Lease PostgresMeshStore::acquire() {
  std::unique_lock lock(mutex_);
  available_.wait(lock, [&] { return !idle_.empty() || open_ < poolSize_; });
  if (!idle_.empty()) {
    PGconn* c = idle_.back();
    idle_.pop_back();
    return Lease(*this, c);
  }
  ++open_;
  lock.unlock();
  try {
    return Lease(*this, connect());
  } catch (...) {
    std::lock_guard relock(mutex_);
    --open_;
    available_.notify_one();
    throw;
  }
}

void PostgresMeshStore::release(PGconn* c) {
  std::lock_guard lock(mutex_);
  // A broken connection (server restarted, network cut) is dropped; the next call reconnects.
  if (PQstatus(c) == CONNECTION_OK && PQtransactionStatus(c) == PQTRANS_IDLE) {
    idle_.push_back(c);
  } else {
    PQfinish(c);
    --open_;
  }
  available_.notify_one();
}

void PostgresMeshStore::createSchema() {
  Lease lease = acquire();
  lease.run("SET client_min_messages = warning");
  lease.run(fmt::format("SELECT pg_advisory_lock({})", kSchemaLockKey));
  try {
    lease.run("CREATE TABLE IF NOT EXISTS tessera_schema (version INTEGER NOT NULL)");
    ResultPtr version = lease.run("SELECT coalesce(max(version), 0) FROM tessera_schema");
    int64_t found = integerAt(version.get(), 0, 0);
    if (found > schema::kVersion) {
      throw StoreError(fmt::format("PostgreSQL store has schema version {}, newer than this "
                                   "server's {}", found, schema::kVersion));
    }
    lease.run(
        "CREATE TABLE IF NOT EXISTS meshes ("
        " id TEXT COLLATE \"C\" PRIMARY KEY, display_name TEXT NOT NULL,"
        " source_format INTEGER NOT NULL, source_bytes BIGINT NOT NULL, boundary INTEGER NOT NULL, vertex_count BIGINT NOT NULL,"
        " face_count BIGINT NOT NULL, face_vertex_count BIGINT NOT NULL,"
        " crease_count BIGINT NOT NULL, corner_count BIGINT NOT NULL,"
        " hole_count BIGINT NOT NULL, min_x DOUBLE PRECISION NOT NULL,"
        " min_y DOUBLE PRECISION NOT NULL, min_z DOUBLE PRECISION NOT NULL,"
        " max_x DOUBLE PRECISION NOT NULL, max_y DOUBLE PRECISION NOT NULL,"
        " max_z DOUBLE PRECISION NOT NULL, sha256 TEXT NOT NULL, create_time_us BIGINT NOT NULL,"
        " stored_bytes BIGINT NOT NULL, content BYTEA NOT NULL)");
    if (found < schema::kVersion) {
      lease.run("DELETE FROM tessera_schema");
      lease.run(fmt::format("INSERT INTO tessera_schema VALUES ({})", schema::kVersion));
    }
  } catch (...) {
    lease.run(fmt::format("SELECT pg_advisory_unlock({})", kSchemaLockKey));
    throw;
  }
  lease.run(fmt::format("SELECT pg_advisory_unlock({})", kSchemaLockKey));
}

bool PostgresMeshStore::insert(const MeshMetadata& metadata, std::string_view content) {
  Params params = metadataParams(metadata);
  params.binary(content);
  std::string values;
  for (int i = 1; i <= params.size(); ++i) values += fmt::format("{}${}", i > 1 ? ", " : "", i);
  Lease lease = acquire();
  ResultPtr r = lease.run(fmt::format("INSERT INTO meshes ({}, content) VALUES ({}) "
                                "ON CONFLICT (id) DO NOTHING",
                                schema::kMetadataColumns, values),
                    params);
  return std::string_view(PQcmdTuples(r.get())) == "1";
}

std::optional<MeshMetadata> PostgresMeshStore::findMetadata(std::string_view id) {
  Params params;
  params.text(std::string(id));
  Lease lease = acquire();
  ResultPtr r = lease.run(fmt::format("SELECT {} FROM meshes WHERE id = $1", schema::kMetadataColumns),
                    params);
  if (PQntuples(r.get()) == 0) return std::nullopt;
  return readMetadata(r.get(), 0);
}

std::optional<StoredMesh> PostgresMeshStore::load(std::string_view id) {
  Params params;
  params.text(std::string(id));
  Lease lease = acquire();
  ResultPtr r = lease.run(fmt::format("SELECT {}, content FROM meshes WHERE id = $1",
                                schema::kMetadataColumns),
                    params);
  if (PQntuples(r.get()) == 0) return std::nullopt;
  return StoredMesh{readMetadata(r.get(), 0), bytea(r.get(), 0, schema::kMetadataColumnCount)};
}

std::vector<MeshMetadata> PostgresMeshStore::list(std::string_view afterId, int limit) {
  Params params;
  params.text(std::string(afterId));
  params.integer(limit);
  Lease lease = acquire();
  // COLLATE "C" orders ids bytewise, as SQLite does, whatever the database's locale.
  ResultPtr r = lease.run(fmt::format("SELECT {} FROM meshes WHERE id COLLATE \"C\" > $1 "
                                "ORDER BY id COLLATE \"C\" LIMIT $2",
                                schema::kMetadataColumns),
                    params);
  std::vector<MeshMetadata> page;
  for (int row = 0; row < PQntuples(r.get()); ++row) page.push_back(readMetadata(r.get(), row));
  return page;
}

bool PostgresMeshStore::remove(std::string_view id) {
  Params params;
  params.text(std::string(id));
  Lease lease = acquire();
  ResultPtr r = lease.run("DELETE FROM meshes WHERE id = $1", params);
  return std::string_view(PQcmdTuples(r.get())) == "1";
}

StoreStats PostgresMeshStore::stats() {
  Lease lease = acquire();
  ResultPtr r =
      lease.run("SELECT count(*), coalesce(sum(stored_bytes), 0) FROM meshes");
  return StoreStats{integerAt(r.get(), 0, 0), integerAt(r.get(), 0, 1)};
}

void PostgresMeshStore::probe() {
  Lease lease = acquire();
  lease.run("SELECT id FROM meshes ORDER BY id LIMIT 1");
}

}  // namespace tessera::server
