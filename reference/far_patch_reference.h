// OpenSubdiv Far's own limit evaluation (patch table isolated to level 10, Gregory end caps), the
// reference for shapes that Debian's Bfr 3.5.0 gets wrong (valence-2 interior vertices, fixed
// upstream in 3.5.1; docs/DECISIONS.md "References in tests"). Exact for every piece at Far level <= 10.
#pragma once

#include <memory>
#include <vector>

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/ptexIndices.h>

#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"
#include "core/topology/far_topology.h"

namespace tessera::testing {

class FarPatchReference {
 public:
  explicit FarPatchReference(const ControlMesh& mesh, int isolationLevel = 10);
  bool evaluate(const PatchDomain& domain, double s, double t, Vec3d& position) const;
  // Limit position at (u, v) of a base face (normalized sub-face coordinates for n-gons, as
  // BfrReference::evaluateFace), with first derivatives in those coordinates when asked for.
  // Const and thread-safe; false for a hole.
  bool evaluateFace(int face, int subFace, double u, double v, Vec3d& position, Vec3d* du = nullptr,
                    Vec3d* dv = nullptr) const;

 private:
  std::unique_ptr<Far::TopologyRefiner> refiner_;
  std::unique_ptr<Far::PatchTable> table_;
  std::unique_ptr<Far::PatchMap> map_;
  std::unique_ptr<Far::PtexIndices> ptex_;
  std::vector<Vec3d> points_;  // refined vertices, then the end caps' local points
};

}  // namespace tessera::testing
