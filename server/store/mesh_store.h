// Durable storage of meshes: metadata plus the canonical encoding, written in one transaction so
// that a mesh is either wholly there or absent, and acknowledged only once committed. Two
// implementations share these semantics: SQLite (one server) and PostgreSQL (replicas sharing
// their meshes).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "server/meshes/mesh_metadata.h"

namespace tessera::server {

// The store could not do its job (I/O error, database gone): the server answers UNAVAILABLE.
class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StoredMesh {
  MeshMetadata metadata;
  std::string content;  // canonical encoding
};

struct StoreStats {
  int64_t meshCount = 0;
  int64_t storedBytes = 0;
};

class MeshStore {
 public:
  virtual ~MeshStore() = default;

  // "sqlite" or "postgresql".
  virtual std::string kind() const = 0;
  // Inserts atomically and durably; returns false (and changes nothing) if the id is taken.
  virtual bool insert(const MeshMetadata& metadata, std::string_view content) = 0;
  virtual std::optional<MeshMetadata> findMetadata(std::string_view id) = 0;
  virtual std::optional<StoredMesh> load(std::string_view id) = 0;
  // Up to limit meshes with id > afterId, in ascending id order.
  virtual std::vector<MeshMetadata> list(std::string_view afterId, int limit) = 0;
  // Returns false if there was no such mesh.
  virtual bool remove(std::string_view id) = 0;
  virtual StoreStats stats() = 0;
  // A cheap read of the meshes table that throws StoreError when the store cannot serve
  // (unreachable, or its table unreadable): what the health service reports (store_health.h).
  virtual void probe() = 0;
};

// Opens the store a --store value names: "sqlite:PATH" or a libpq URI "postgresql://..." /
// "postgres://...". Throws StoreError when it cannot. `timeout`: how long a PostgreSQL connection
// or statement may go without progress before it fails (SQLite is a local file).
std::unique_ptr<MeshStore> openMeshStore(const std::string& spec, std::chrono::milliseconds timeout);

}  // namespace tessera::server
