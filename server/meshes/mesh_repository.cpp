#include "server/meshes/mesh_repository.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>

#include "core/base/sha256.h"
#include "core/mesh/mesh_codec.h"
#include "server/calls/status_error.h"
#include "server/meshes/mesh_names.h"

namespace tessera::server {
namespace {

const std::string& cacheKey(const MeshMetadata& m) { return m.sha256; }

int64_t nowMicros() {
  using namespace std::chrono;
  return duration_cast<microseconds>(system_clock::now().time_since_epoch()).count();
}

[[noreturn]] void notFound(const std::string& id) {
  throwStatus(grpc::StatusCode::NOT_FOUND, fmt::format("mesh {} not found", meshName(id)));
}

// Runs a store call; a store failure becomes UNAVAILABLE, which clients may retry. The store's
// own words (its library's message, host names, file names) go to the log, not to the client.
template <typename F>
auto storeCall(F&& call) -> decltype(call()) {
  try {
    return call();
  } catch (const StoreError& error) {
    spdlog::error("store: {}", error.what());
    throwStatus(grpc::StatusCode::UNAVAILABLE, "mesh store unavailable; the server's log has the cause");
  }
}

}  // namespace

MeshMetadata MeshRepository::create(ControlMesh mesh, MeshMetadata metadata) {
  std::string content = encodeCanonicalMesh(mesh);
  describeMesh(mesh, metadata);
  metadata.sha256 = sha256Hex(content);
  metadata.storedBytes = static_cast<int64_t>(content.size());
  metadata.createTimeMicros = nowMicros();
  if (!storeCall([&] { return store_.insert(metadata, content); })) {
    throwStatus(grpc::StatusCode::ALREADY_EXISTS,
                fmt::format("mesh {} already exists", meshName(metadata.id)));
  }
  size_t bytes = meshHeapBytes(mesh);
  cache_.insert(cacheKey(metadata), std::make_shared<const ControlMesh>(std::move(mesh)), bytes);
  return metadata;
}

MeshMetadata MeshRepository::metadata(const std::string& id) {
  auto found = storeCall([&] { return store_.findMetadata(id); });
  if (!found) notFound(id);
  return *found;
}

bool MeshRepository::exists(const std::string& id) {
  return storeCall([&] { return store_.findMetadata(id); }).has_value();
}

std::vector<MeshMetadata> MeshRepository::list(const std::string& afterId, int limit) {
  return storeCall([&] { return store_.list(afterId, limit); });
}

void MeshRepository::remove(const std::string& id) {
  auto found = storeCall([&] { return store_.findMetadata(id); });
  if (!found || !storeCall([&] { return store_.remove(id); })) notFound(id);
  cache_.erase(cacheKey(*found));
}

std::shared_ptr<const ControlMesh> MeshRepository::mesh(const MeshMetadata& metadata) {
  const std::string key = cacheKey(metadata);
  if (auto cached = cache_.find(key)) return cached;
  auto stored = storeCall([&] { return store_.load(metadata.id); });
  if (!stored || stored->metadata.sha256 != metadata.sha256) notFound(metadata.id);
  // Checked on every load from the store: corruption is reported, never tessellated.
  if (sha256Hex(stored->content) != metadata.sha256) {
    throwStatus(grpc::StatusCode::DATA_LOSS,
                fmt::format("mesh {}: stored content does not match its checksum",
                            meshName(metadata.id)));
  }
  std::shared_ptr<const ControlMesh> mesh;
  try {
    mesh = std::make_shared<const ControlMesh>(decodeCanonicalMesh(stored->content));
  } catch (const MeshDecodeError& error) {
    throwStatus(grpc::StatusCode::DATA_LOSS,
                fmt::format("mesh {}: {}", meshName(metadata.id), error.what()));
  }
  cache_.insert(key, mesh, meshHeapBytes(*mesh));
  return mesh;
}

StoreStats MeshRepository::storeStats() {
  return storeCall([&] { return store_.stats(); });
}

}  // namespace tessera::server
