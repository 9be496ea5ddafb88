// Bridge from Tessera's ControlMesh to OpenSubdiv Far: the topology refiner (with creases,
// corners, holes and boundary options) and double-precision positions of its refined levels.
#pragma once

#include <memory>
#include <vector>

#include <opensubdiv/far/topologyRefiner.h>

#include "core/control_mesh.h"
#include "core/vec3.h"

namespace tessera {

namespace Far = OpenSubdiv::Far;

std::unique_ptr<Far::TopologyRefiner> createTopologyRefiner(const ControlMesh& mesh);

// Positions of every vertex of every refined level, levels concatenated (Far's numbering with
// the base level included), computed in double precision.
std::vector<Vec3d> refinedPositions(const Far::TopologyRefiner& refiner,
                                    const std::vector<Vec3>& basePositions);

// Largest finite (semi-sharp) sharpness among creases and corners; 0 if none.
float maxSemiSharpness(const ControlMesh& mesh);

}  // namespace tessera
