// The server's view of its meshes: the store for durability plus a byte-bounded cache of decoded
// meshes, with the gRPC-facing errors (NOT_FOUND, ALREADY_EXISTS, UNAVAILABLE, DATA_LOSS) decided
// here once. Cache entries are keyed by content checksum alone (the SHA-256 of the canonical
// encoding, which the metadata read from the store gives): one content under several ids is
// decoded and kept once, and a replica never serves a mesh that another replica deleted and
// re-created under the same id with other content.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "server/meshes/lru_cache.h"
#include "server/meshes/mesh_metadata.h"
#include "server/store/mesh_store.h"

namespace tessera::server {

using MeshCache = LruCache<std::string, ControlMesh>;

class MeshRepository {
 public:
  MeshRepository(MeshStore& store, size_t cacheBytes) : store_(store), cache_(cacheBytes) {}

  // Stores a new mesh (metadata carries id, display name and source; the rest is computed) and
  // returns its complete metadata. Throws StatusError ALREADY_EXISTS if the id is taken.
  MeshMetadata create(ControlMesh mesh, MeshMetadata metadata);
  // Throws StatusError NOT_FOUND.
  MeshMetadata metadata(const std::string& id);
  bool exists(const std::string& id);
  std::vector<MeshMetadata> list(const std::string& afterId, int limit);
  // Throws StatusError NOT_FOUND.
  void remove(const std::string& id);
  // The decoded mesh, from the cache or the store (checked against its checksum).
  std::shared_ptr<const ControlMesh> mesh(const MeshMetadata& metadata);

  CacheStats cacheStats() const { return cache_.stats(); }
  StoreStats storeStats();
  std::string storeKind() const { return store_.kind(); }

 private:
  MeshStore& store_;
  MeshCache cache_;
};

}  // namespace tessera::server
