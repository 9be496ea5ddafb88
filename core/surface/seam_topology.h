// Where roots meet (docs/ADAPTIVE.md §5): the base edge or n-gon spoke each root side lies on and
// its parameter there, and where the surface is not tangent-continuous, so that vertices there
// get one normal per side (seam_lines.h numbers the lines and the points they share). Roots are a
// quad base face or one quad sub-face of an n-gon; sub-face k has (0,0) at corner k, (1,0) at
// the middle of edge k, (1,1) at the centre and (0,1) at the middle of edge k − 1.
//
// Tile corners are dyadic: root coordinates are integers at scale 2^kRootBits, and positions
// along base edges and spokes integers at scale 2^kLineBits (a sub-face covers half an edge).
#pragma once

#include <cstddef>
#include <cstdint>
#include <tuple>
#include <vector>

#include "core/mesh/control_mesh.h"

namespace tessera {

inline constexpr int kRootBits = 50;
inline constexpr int kLineBits = kRootBits + 1;
inline constexpr int64_t kRootScale = int64_t(1) << kRootBits;
// Root coordinate (scale kRootScale) of the i-th side of squares of `level`.
constexpr int64_t rootCoordinate(int level, uint64_t i) { return int64_t(i) << (kRootBits - level); }
inline constexpr int64_t kLineScale = int64_t(1) << kLineBits;

// A line roots share: a base edge (lower vertex first) or spoke k of an n-gon (from the middle of
// edge k to the centre).
struct SeamLine {
  enum Kind : uint8_t { kEdge, kSpoke } kind = kEdge;
  int a = 0, b = 0;  // edge (lo, hi) | spoke (face, k)

  friend bool operator<(const SeamLine& x, const SeamLine& y) {
    return std::tie(x.kind, x.a, x.b) < std::tie(y.kind, y.a, y.b);
  }
  friend bool operator==(const SeamLine& x, const SeamLine& y) {
    return x.kind == y.kind && x.a == y.a && x.b == y.b;
  }
};

struct SeamTopology {
  std::vector<int> faceSizes, faceVertices, faceOffsets;
  std::vector<std::pair<int, int>> sharpEdges;  // infinitely sharp base edges (lo, hi), sorted
  std::vector<int> cornerWedge;                 // per face corner: its wedge id, or -1 (one normal)
  // Per face corner: both edges there are shared with the same other face (a valence-2 vertex),
  // or the face folds there (both edges are one input edge, or one has collapsed to the vertex):
  // a tile there needs a point inside, or its triangles would lie back to back or collapse.
  std::vector<uint8_t> cornerPinched;

  explicit SeamTopology(const ControlMesh& mesh);
  SeamTopology() = default;
  int corner(int face, int k) const {
    const int n = faceSizes[face];
    return faceVertices[faceOffsets[face] + ((k % n) + n) % n];
  }
  bool sharp(int v0, int v1) const;
  size_t bytes() const;
  bool pinched(int face, int k) const { return cornerPinched[faceOffsets[face] + k] != 0; }
  // Wedge of corner k of face f (the smallest face id of the wedge), -1 where one normal serves
  // every face around the vertex.
  int wedge(int face, int k) const {
    const int n = faceSizes[face];
    return cornerWedge[faceOffsets[face] + ((k % n) + n) % n];
  }
};

// A root side (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0) on its line: t = origin + sign·s/halves
// for the side's own coordinate s (u on sides 0 and 2, v on sides 1 and 3), t and s in [0, 1].
struct SideLine {
  SeamLine line;
  int origin = 0;   // 0 or 1
  int sign = 1;     // ±1
  int halves = 1;   // 1, or 2 where a sub-face covers half a base edge
  bool sharp = false;  // an infinitely sharp base edge
};

SideLine rootSideLine(const SeamTopology& topology, int face, int subFace, int side);

}  // namespace tessera
