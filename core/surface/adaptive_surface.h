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

namespace tessera {

struct AdaptiveSurface {
  SurfaceTree tree;
  SeamTopology seams;
  RootSeams rootSeams;
  SeamLines lines;

  size_t bytes() const;
};

// The surface tree over `patches` (reduced from a mesh of `vertexCount` vertices whose manifold
// sheets have the faces `sheetFaces`; positions are not read), its chains down to `chainFloor`
// (surface_tree.h), and the seams between its roots (`seams`, the mesh's seam topology, copied).
// `checkpoint`, when given, is called for every root and between the stages, and may throw to
// abandon the work.
std::shared_ptr<const AdaptiveSurface> buildAdaptiveSurface(const PatchSet& patches, const ControlMesh& sheetFaces,
                                                            const SeamTopology& seams, int vertexCount,
                                                            const std::function<void()>& checkpoint,
                                                            double chainFloor = kChainFloor);

}  // namespace tessera
