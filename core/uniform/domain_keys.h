// Canonical names for the lines and points of the surface's parameter domain, so that the two
// pieces on either side of an edge agree on it even when they lie in different base faces
// (watertightness by sharing, MATH.md §5). Points and lines on a base edge are named by the edge
// (lower vertex first); the spokes of an n-gon's quad sub-faces by face and spoke; everything
// else by its face and exact dyadic coordinates.
#pragma once

#include <tuple>
#include <vector>

namespace tessera {

struct DomainKey {
  enum Kind : int { kVertex, kEdge, kSpoke, kCenter, kInterior } kind;
  int a = 0, b = 0, c = 0;   // vertex | edge (lo, hi) | face, spoke | face | face, sub-face, axis
  double x = 0, y = 0;       // parameter on a line | coordinates of an interior point
  bool operator<(const DomainKey& o) const {
    return std::tie(kind, a, b, c, x, y) < std::tie(o.kind, o.a, o.b, o.c, o.x, o.y);
  }
  bool operator==(const DomainKey& o) const {
    return std::tie(kind, a, b, c, x, y) == std::tie(o.kind, o.a, o.b, o.c, o.x, o.y);
  }
};

// The base mesh's faces, to name edges by their vertices.
struct FaceTopology {
  const std::vector<int>& faceSizes;
  const std::vector<int>& faceVertices;
  std::vector<int> offsets;
  FaceTopology(const std::vector<int>& sizes, const std::vector<int>& vertices);
  int corner(int face, int k) const;  // k taken modulo the face size
  int size(int face) const { return faceSizes[face]; }
};

// A point (u, v) of face `face` (sub-face `subFace` of an n-gon, -1 for a quad).
DomainKey pointKey(const FaceTopology& faces, int face, int subFace, double u, double v);

// The line through (u, v) along which `alongU` varies (the other coordinate is constant), and
// the parameter of (u, v) on it.
DomainKey lineKey(const FaceTopology& faces, int face, int subFace, double u, double v, bool alongU,
                  double& parameter);

}  // namespace tessera
