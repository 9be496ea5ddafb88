// Which roots share each base edge or spoke, and where each lies on it: mesh data, built once
// beside the seam topology (core/surface/adaptive_surface.h), that planning asks whenever a tile
// side on a root's boundary needs the tiles across it (core/adaptive/tile_neighbors.h).
#pragma once

#include <cstdint>
#include <vector>

#include "core/surface/seam_topology.h"
#include "core/surface/surface_tree.h"

namespace tessera {

// For every root side on a base edge or spoke, the other root sides on the same line and where
// each lies on it (t in [t0, t1], scale kLineScale). Mesh data: cached with the patch set.
struct RootSeams {
  struct Span {
    uint32_t root;
    uint8_t side;
    int64_t t0, t1;
    SideLine line;
  };
  std::vector<uint32_t> first;  // 4 per root + 1: spans of the other roots on root side k's line
  std::vector<Span> spans;
  std::vector<Span> own;  // each root side's own span

  RootSeams() = default;
  RootSeams(const SurfaceTree& tree, const SeamTopology& seams);
};

}  // namespace tessera
