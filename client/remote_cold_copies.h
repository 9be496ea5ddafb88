// Copies of a stored mesh that the server has never seen, for measuring its cold path (issue 46):
// the server keys preprocessing by the mesh's content (its SHA-256), so a copy under a new id
// would be served warm; each copy here moves every vertex by a small smooth displacement that
// depends on the copy's index, and so has content of its own, the same topology, creases and
// rules, and the same shape to within kColdDisplacement of the bounding-box diagonal.
// `tessera bench --cold` and tools/soak's cold storm use it.
#pragma once

#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <string>

#include "tessera/v1/mesh.grpc.pb.h"

namespace tessera::cli {

// The largest move of a vertex along each axis, as a fraction of the bounding-box diagonal.
inline constexpr double kColdDisplacement = 3e-3;

// A stored mesh, read back to be copied.
struct ColdSource {
  std::string name;  // meshes/ID
  tessera::v1::MeshArrays arrays;
  tessera::v1::SubdivisionOptions options;  // the copies are uploaded with the same rules
  double diagonal = 0;                      // of its bounding box
};

// Reads meshes/ID back (DownloadMesh); the call's status, *source filled on success.
grpc::Status readColdSource(tessera::v1::MeshService::Stub& stub, grpc::ClientContext& context,
                            const std::string& name, ColdSource* source);

// Copy number `index` of source's arrays: x, y and z each moved by
// kColdDisplacement * diagonal * sin(2π (2 c / diagonal + φ)), c another coordinate of the
// vertex and φ a phase that the index sets. Deterministic; different indices give different
// positions.
tessera::v1::MeshArrays coldCopy(const ColdSource& source, uint64_t index);

}  // namespace tessera::cli
