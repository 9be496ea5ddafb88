// What the server knows about a stored mesh besides its arrays: enough to answer GetMesh and
// ListMeshes without decoding the mesh.
#pragma once

#include <cstdint>
#include <string>

#include "core/base/vec3.h"
#include "core/mesh/control_mesh.h"

namespace tessera::server {

// Numbered as tessera.v1.MeshFormat, which is also how the stores persist it.
enum class SourceFormat : int32_t { kArrays = 1, kObj = 2 };

// The `boundary` column holds rulesCode (core/mesh/subdivision_rules.h): rows written before crease and
// triangle rules were stored hold 1 or 2 and read as uniform creases and Catmull-Clark triangles.
// Throws StoreError naming the mesh for a number no rules encode.
SubdivisionRules rulesFromColumn(int64_t code, const std::string& id);

struct MeshMetadata {
  std::string id;
  std::string displayName;
  SourceFormat sourceFormat = SourceFormat::kArrays;
  int64_t sourceBytes = 0;
  SubdivisionRules rules;
  int64_t vertexCount = 0;
  int64_t faceCount = 0;
  int64_t faceVertexCount = 0;
  int64_t creaseCount = 0;
  int64_t cornerCount = 0;
  int64_t holeCount = 0;
  Vec3d boundsMin;
  Vec3d boundsMax;
  std::string sha256;            // hex, of the canonical encoding
  int64_t createTimeMicros = 0;  // since the Unix epoch
  int64_t storedBytes = 0;       // size of the canonical encoding

  double boundsDiagonal() const { return length(boundsMax - boundsMin); }
};

// Counts and bounds of mesh (everything that does not depend on how it arrived).
void describeMesh(const ControlMesh& mesh, MeshMetadata& metadata);

}  // namespace tessera::server
