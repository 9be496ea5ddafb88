// `tessera upload --topology-of meshes/NAME NEW.obj`: an edit of a stored mesh sent as its
// positions alone (mesh.proto, UploadMeshHeader.topology_of). The OBJ is read here and its
// topology checked against the stored mesh's, downloaded for the purpose, so that the positions
// never land on faces they were not meant for; its UVs go only where they differ.
#pragma once

#include <stdexcept>
#include <string>

#include "core/mesh/control_mesh.h"
#include "tessera/v1/mesh.pb.h"

namespace tessera::cli {

// The OBJ's topology is not the stored mesh's (exit code kExitInvalidInput).
class TopologyMismatch : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a positions-only upload of `local` (read from `source`) on the topology of the stored
// mesh `name` (its arrays `stored`, as DownloadMesh sends them) carries: the positions, the UVs
// when they differ, the origin when there is one; and `local`'s rules in `rules`, which the
// server checks against the stored mesh's. Throws TopologyMismatch naming the first difference
// (counts, a face, a crease, a corner, a hole, a UV index).
tessera::v1::MeshArrays positionsOnlyArrays(const ControlMesh& local, const std::string& source,
                                            const std::string& name,
                                            const tessera::v1::MeshArrays& stored,
                                            tessera::v1::SubdivisionOptions* rules);

}  // namespace tessera::cli
