// What the adaptive tessellation caches per mesh beside its patch set: the surface tree and the
// seams between roots (built once by buildPatchSet).
#pragma once

#include "core/surface/seam_lines.h"
#include "core/surface/seam_topology.h"
#include "core/surface/surface_tree.h"
#include "core/adaptive/tile_neighbors.h"

namespace tessera {

struct AdaptiveSurface {
  SurfaceTree tree;
  SeamTopology seams;
  RootSeams rootSeams;
  SeamLines lines;

  size_t bytes() const;
};

}  // namespace tessera
