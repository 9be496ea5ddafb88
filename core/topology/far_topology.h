// Bridge from Tessera's ControlMesh to OpenSubdiv Far: the topology refiner (with creases,
// corners, holes and boundary options) and double-precision positions of its refined levels.
#pragma once

#include <memory>
#include <vector>

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/topologyRefiner.h>

#include "core/base/vec3.h"
#include "core/mesh/control_mesh.h"

namespace tessera {

namespace Far = OpenSubdiv::Far;

// withUvs: with the mesh's UVs as face-varying channel 0 (the patch set's refiner has none).
std::unique_ptr<Far::TopologyRefiner> createTopologyRefiner(const ControlMesh& mesh, bool withUvs = false);

// Positions of every vertex of every refined level, levels concatenated (Far's numbering with
// the base level included), computed in double precision.
std::vector<Vec3d> refinedPositions(const Far::TopologyRefiner& refiner,
                                    const std::vector<Vec3>& basePositions);

// Largest finite (semi-sharp) sharpness among creases and corners; 0 if none.
float maxSemiSharpness(const ControlMesh& mesh);

// The feature-adaptive isolation level the patch set needs: smooth EVs need two levels to be
// isolated, semi-sharp features their sharpness to decay (at most 10).
int isolationLevelFor(const ControlMesh& mesh);

// The patch table the patch set is made from (bilinear end caps, infinitely sharp patches), to
// `isolation` levels, and Far's adaptive refinement for it.
Far::PatchTableFactory::Options patchTableOptions(int isolation);
void refineAdaptively(Far::TopologyRefiner& refiner, const Far::PatchTableFactory::Options& options);

}  // namespace tessera
