// MeshStore on PostgreSQL through libpq, for several server replicas that share their meshes.
// Same table and semantics as the SQLite store: one INSERT per upload, committed before the
// upload is acknowledged (synchronous_commit as the database sets it, "on" by default).
#pragma once

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "server/store/mesh_store.h"

struct pg_conn;
struct pg_result;

namespace tessera::server {

class PostgresMeshStore final : public MeshStore {
 public:
  // conninfo: a libpq URI or keyword=value string. Connects once to check it and create the
  // table; throws StoreError if that fails. Every connection and every statement must make
  // progress within `timeout` (StoreError otherwise, and the connection is dropped).
  PostgresMeshStore(std::string conninfo, std::chrono::milliseconds timeout, int poolSize = 4);
  ~PostgresMeshStore() override;
  PostgresMeshStore(const PostgresMeshStore&) = delete;
  PostgresMeshStore& operator=(const PostgresMeshStore&) = delete;

  std::string kind() const override { return "postgresql"; }
  bool insert(const MeshMetadata& metadata, std::string_view content) override;
  std::optional<MeshMetadata> findMetadata(std::string_view id) override;
  std::optional<StoredMesh> load(std::string_view id) override;
  std::vector<MeshMetadata> list(std::string_view afterId, int limit) override;
  bool remove(std::string_view id) override;
  StoreStats stats() override;
  void probe() override;

 private:
  class Lease;
  Lease acquire();
  void release(pg_conn* connection);
  pg_conn* connect();
  void createSchema();

  std::string conninfo_;
  std::chrono::milliseconds timeout_;
  size_t poolSize_;
  std::mutex mutex_;
  std::condition_variable available_;
  std::vector<pg_conn*> idle_;
  size_t open_ = 0;  // connections that exist, idle or leased
};

}  // namespace tessera::server
