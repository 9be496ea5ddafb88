// OpenSubdiv as the independent reference: Far's refinement of a mesh gathered in CER order.
#pragma once

#include <memory>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/topology/far_topology.h"
#include "core/topology/lattice_walker.h"

namespace tessera::testing {

// A uniformly refined copy of `mesh` with double-precision positions for every level.
struct FarRefinement {
  std::unique_ptr<Far::TopologyRefiner> refiner;
  std::vector<Vec3d> positions;
  std::vector<int> levelOffsets;

  static FarRefinement uniform(const ControlMesh& mesh, int levels);
  static FarRefinement adaptive(const ControlMesh& mesh, int isolationLevel);
  Vec3d position(int level, Index v) const { return positions[levelOffsets[level] + v]; }
};

// Far's refined (12n+1) set around the child of `ev` at `level`, whose first spoke is the
// child of edge (ev, firstSpoke) of level - 1; also returns the vertices for the next level.
struct FarRingLevel {
  std::vector<Vec3d> refinedPoints;  // CER refined order; NaN where Far's level is incomplete
  Index ev = -1, firstSpoke = -1;
};
FarRingLevel farRingLevel(const FarRefinement& far, int level, Index parentEv, Index parentSpoke);

}  // namespace tessera::testing
