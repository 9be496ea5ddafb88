#include "server/meshes/mesh_metadata.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/mesh/subdivision_rules.h"
#include "server/store/mesh_store.h"

namespace tessera::server {

void describeMesh(const ControlMesh& mesh, MeshMetadata& metadata) {
  metadata.rules = mesh.rules;
  metadata.vertexCount = mesh.vertexCount();
  metadata.faceCount = mesh.faceCount();
  metadata.faceVertexCount = static_cast<int64_t>(mesh.faceVertices.size());
  metadata.creaseCount = static_cast<int64_t>(mesh.creases.size());
  metadata.cornerCount = static_cast<int64_t>(mesh.corners.size());
  metadata.holeCount = static_cast<int64_t>(mesh.holes.size());
  if (mesh.positions.empty()) {
    metadata.boundsMin = metadata.boundsMax = Vec3d();
    return;
  }
  Vec3d lo(mesh.positions.front()), hi(mesh.positions.front());
  for (const Vec3& p : mesh.positions) {
    lo = Vec3d(std::min<double>(lo.x, p.x), std::min<double>(lo.y, p.y),
               std::min<double>(lo.z, p.z));
    hi = Vec3d(std::max<double>(hi.x, p.x), std::max<double>(hi.y, p.y),
               std::max<double>(hi.z, p.z));
  }
  // In model units: the positions are relative to the mesh's origin.
  metadata.boundsMin = lo + mesh.origin;
  metadata.boundsMax = hi + mesh.origin;
}

SubdivisionRules rulesFromColumn(int64_t code, const std::string& id) {
  const std::optional<SubdivisionRules> rules =
      code >= 0 && code <= UINT32_MAX ? rulesFromCode(uint32_t(code)) : std::nullopt;
  if (!rules) throw StoreError(fmt::format("mesh {}: unknown subdivision rules code {}", id, code));
  return *rules;
}

}  // namespace tessera::server
