// openMeshStore(): the --store value decides the implementation.
#include <string_view>

#include "server/store/mesh_store.h"
#include "server/store/postgres_mesh_store.h"
#include "server/store/sqlite_mesh_store.h"

namespace tessera::server {

std::unique_ptr<MeshStore> openMeshStore(const std::string& spec, std::chrono::milliseconds timeout) {
  constexpr std::string_view kSqlite = "sqlite:";
  std::string_view s = spec;
  if (s.substr(0, kSqlite.size()) == kSqlite) {
    std::string path(s.substr(kSqlite.size()));
    if (path.empty()) throw StoreError("--store sqlite:PATH needs a path");
    return std::make_unique<SqliteMeshStore>(path);
  }
  if (s.substr(0, 13) == "postgresql://" || s.substr(0, 11) == "postgres://") {
    return std::make_unique<PostgresMeshStore>(spec, timeout);
  }
  throw StoreError("--store must be sqlite:PATH or a postgresql:// URI (got \"" + spec + "\")");
}

}  // namespace tessera::server
