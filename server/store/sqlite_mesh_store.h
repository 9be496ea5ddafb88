// MeshStore on an embedded SQLite database in WAL mode with synchronous=FULL: a commit reaches
// the disk before insert() returns, so an acknowledged upload survives SIGKILL and power loss.
#pragma once

#include <mutex>
#include <string>

#include "server/store/mesh_store.h"

struct sqlite3;

namespace tessera::server {

class SqliteMeshStore final : public MeshStore {
 public:
  explicit SqliteMeshStore(const std::string& path);
  ~SqliteMeshStore() override;
  SqliteMeshStore(const SqliteMeshStore&) = delete;
  SqliteMeshStore& operator=(const SqliteMeshStore&) = delete;

  std::string kind() const override { return "sqlite"; }
  bool insert(const MeshMetadata& metadata, std::string_view content) override;
  std::optional<MeshMetadata> findMetadata(std::string_view id) override;
  std::optional<StoredMesh> load(std::string_view id) override;
  std::vector<MeshMetadata> list(std::string_view afterId, int limit) override;
  bool remove(std::string_view id) override;
  StoreStats stats() override;
  void probe() override;

 private:
  void exec(const char* sql);
  void createSchema();

  // One connection serialised by a mutex: meshes are read through the cache, so the store sees
  // few calls, and SQLite allows one writer at a time anyway.
  std::mutex mutex_;
  sqlite3* db_ = nullptr;
  std::string path_;
};

}  // namespace tessera::server
