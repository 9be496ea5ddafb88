// What the adaptive tessellation caches per mesh beside its patch set: the surface tree and the
// seams between roots, built once when the mesh is preprocessed (core/pipeline/preprocessing.h).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"
#include "core/surface/root_seams.h"
#include "core/surface/seam_lines.h"
#include "core/surface/seam_topology.h"
#include "core/surface/surface_tree.h"
#include "core/topology/refinement_input.h"

namespace tessera {

struct AdaptiveSurface {
  SurfaceTree tree;
  SeamTopology seams;
  RootSeams rootSeams;
  SeamLines lines;

  size_t bytes() const;
};

// The surface tree over `patches` (reduced from `input`'s sheets of `mesh`), its chains down to
// `chainFloor` (surface_tree.h), and the seams between its roots. `checkpoint`, when given, is
// called for every root and between the stages, and may throw to abandon the work.
std::shared_ptr<const AdaptiveSurface> buildAdaptiveSurface(const PatchSet& patches, const RefinementInput& input,
                                                            const ControlMesh& mesh,
                                                            const std::function<void()>& checkpoint,
                                                            double chainFloor = kChainFloor);

}  // namespace tessera
