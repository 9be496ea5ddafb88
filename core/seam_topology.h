// Where roots meet (docs/ADAPTIVE.md §5): the line each tile side lies on and its exact
// parameter there, canonical names for points that several roots or lines share, and where the
// surface is not tangent-continuous, so that vertices there get one normal per side. Roots are a
// quad base face or one quad sub-face of an n-gon; sub-face k has (0,0) at corner k, (1,0) at
// the middle of edge k, (1,1) at the centre and (0,1) at the middle of edge k − 1.
#pragma once

#include <cstdint>
#include <tuple>
#include <vector>

#include "core/control_mesh.h"
#include "core/fraction.h"

namespace tessera {

// A line of the parameter domain: a base edge (lower vertex first), an n-gon's spoke from the
// middle of edge k to the centre, or a line inside one root at a fixed u (axis 0) or v (axis 1).
struct LineKey {
  enum Kind : uint8_t { kEdge, kSpoke, kInterior } kind = kEdge;
  uint8_t axis = 0;
  int a = 0, b = 0;  // edge (lo, hi) | spoke (face, k) | interior (root, -)
  Fraction fixed;    // interior: the fixed coordinate

  friend bool operator<(const LineKey& x, const LineKey& y) {
    if (x.kind != y.kind) return x.kind < y.kind;
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    if (x.axis != y.axis) return x.axis < y.axis;
    return x.fixed < y.fixed;
  }
  friend bool operator==(const LineKey& x, const LineKey& y) {
    return x.kind == y.kind && x.a == y.a && x.b == y.b && x.axis == y.axis && x.fixed == y.fixed;
  }
};

// A point of the domain, named the same from every root and line that holds it.
struct PointKey {
  enum Kind : uint8_t { kVertex, kEdge, kSpoke, kCenter, kInterior } kind = kVertex;
  int a = 0, b = 0;  // vertex | edge (lo, hi) | spoke (face, k) | centre face | interior root
  Fraction x, y;     // parameter on the edge or spoke | (u, v) inside the root

  friend bool operator<(const PointKey& p, const PointKey& q) {
    if (p.kind != q.kind) return p.kind < q.kind;
    if (p.a != q.a) return p.a < q.a;
    if (p.b != q.b) return p.b < q.b;
    if (!(p.x == q.x)) return p.x < q.x;
    return p.y < q.y;
  }
  friend bool operator==(const PointKey& p, const PointKey& q) {
    return p.kind == q.kind && p.a == q.a && p.b == q.b && p.x == q.x && p.y == q.y;
  }
};

// How a point's normal is chosen where the surface has a crease: one normal for everyone, one per
// base face (inside an infinitely sharp edge), or one per wedge of faces around a base vertex
// that sharp edges separate (or per face at an infinitely sharp corner).
enum class NormalSplit : uint8_t { kNone, kByFace, kByWedge };

struct SeamTopology {
  std::vector<int> faceSizes, faceVertices, faceOffsets;
  std::vector<std::pair<int, int>> sharpEdges;  // infinitely sharp base edges (lo, hi), sorted
  std::vector<int> cornerWedge;                 // per face corner: its wedge id, or -1 (one normal)

  explicit SeamTopology(const ControlMesh& mesh);
  SeamTopology() = default;
  int corner(int face, int k) const {
    const int n = faceSizes[face];
    return faceVertices[faceOffsets[face] + ((k % n) + n) % n];
  }
  bool sharp(int v0, int v1) const;
  // Wedge of corner k of face f (the smallest face id of the wedge), -1 for a smooth vertex.
  int wedge(int face, int k) const {
    const int n = faceSizes[face];
    return cornerWedge[faceOffsets[face] + ((k % n) + n) % n];
  }
};

// A root side (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0) on its line: parameter t = origin + scale·s
// for the side's own coordinate s (u on sides 0 and 2, v on sides 1 and 3).
struct SideLine {
  LineKey line;
  Fraction origin;
  int scaleNum = 1, scaleDen = 1;  // ±1 or ±1/2
  bool sharp = false;              // an infinitely sharp base edge

  Fraction at(const Fraction& s) const { return origin + s.times(scaleNum).over(scaleDen); }
};

SideLine rootSideLine(const SeamTopology& topology, int face, int subFace, int side);

// The canonical name of point (u, v) of a root, and how its normal splits (the wedge or face id
// that qualifies it, -1 for kNone).
PointKey rootPointKey(const SeamTopology& topology, int face, int subFace, const Fraction& u, const Fraction& v);
// The point at parameter t of a line; `face`, `subFace`: the root of an interior line.
PointKey linePointKey(const SeamTopology& topology, const LineKey& line, const Fraction& t, int face, int subFace);
NormalSplit normalSplitAt(const SeamTopology& topology, int face, int subFace, const Fraction& u,
                          const Fraction& v, int& qualifier);

}  // namespace tessera
