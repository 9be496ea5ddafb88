// The lines roots share, numbered once per mesh (docs/ADAPTIVE.md §5): every base edge and n-gon
// spoke some root side lies on, the root sides on each, and the points several lines share
// (nodes: base vertices, n-gon centres, the middles of edges that n-gon sub-faces halve). With
// these, stitching joins the roots line by line with no search for shared names.
#pragma once

#include <cstdint>
#include <vector>

#include "core/surface/seam_topology.h"
#include "core/surface/surface_tree.h"

namespace tessera {

inline constexpr uint32_t kNoSeamNode = UINT32_MAX;

struct SeamLines {
  struct Line {
    uint32_t firstSide = 0, sideCount = 0;  // its root sides: rootSides[firstSide, + sideCount)
    // Nodes at t = 0, t = 1/2 (kNoSeamNode unless sub-faces halve the edge) and t = 1.
    uint32_t node[3] = {kNoSeamNode, kNoSeamNode, kNoSeamNode};
    bool sharp = false;  // an infinitely sharp base edge
  };
  std::vector<Line> lines;
  std::vector<uint32_t> rootSides;  // root side 4r + k, line by line, ascending
  std::vector<uint32_t> lineOf;     // per root side, its line (every side of a root that is not a hole)
  std::vector<SideLine> sideLine;   // per root side, where it lies on its line
  // Per root corner 4r + c (c: (0,0), (1,0), (1,1), (0,1)): how a vertex there splits its normal
  // for this root (seam_topology.h's qualifier).
  std::vector<int> cornerQualifier;
  // The lines by the root of their first side (the lowest): root r's are
  // linesByRoot[rootFirstLine[r], rootFirstLine[r + 1]). Stitching resolves a line on the core
  // that stitched that root (parallel_chunks.h).
  std::vector<uint32_t> linesByRoot, rootFirstLine;
  // Nodes: base vertices [0, V), n-gon centres V + face, edge middles V + F + line.
  uint32_t nodeCount = 0;

  SeamLines() = default;
  SeamLines(const SurfaceTree& tree, const SeamTopology& seams, int vertexCount);
  size_t bytes() const;
};

}  // namespace tessera
