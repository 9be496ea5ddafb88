#include "core/uniform/domain_keys.h"

namespace tessera {

FaceTopology::FaceTopology(const std::vector<int>& sizes, const std::vector<int>& vertices)
    : faceSizes(sizes), faceVertices(vertices) {
  offsets.reserve(sizes.size());
  int offset = 0;
  for (int s : sizes) {
    offsets.push_back(offset);
    offset += s;
  }
}

int FaceTopology::corner(int face, int k) const {
  int n = faceSizes[face];
  return faceVertices[offsets[face] + ((k % n) + n) % n];
}

namespace {

// A position `fromA` along base edge (a -> b), named from its lower vertex.
DomainKey edgeLine(int a, int b, double fromA, double& parameter) {
  parameter = a < b ? fromA : 1.0 - fromA;
  return {DomainKey::kEdge, a < b ? a : b, a < b ? b : a, 0, 0, 0};
}

DomainKey onEdge(int a, int b, double fromA) {
  double t;
  DomainKey line = edgeLine(a, b, fromA, t);
  if (t == 0.0) return {DomainKey::kVertex, line.a, 0, 0, 0, 0};
  if (t == 1.0) return {DomainKey::kVertex, line.b, 0, 0, 0, 0};
  line.x = t;
  return line;
}

DomainKey onSpoke(const FaceTopology& faces, int face, int spoke, double t) {
  if (t == 1.0) return {DomainKey::kCenter, face, 0, 0, 0, 0};
  int n = faces.size(face);
  return {DomainKey::kSpoke, face, ((spoke % n) + n) % n, 0, t, 0};
}

}  // namespace

// Quad: corners 0..3 at (0,0),(1,0),(1,1),(0,1). Quad sub-face k of an n-gon: (0,0) at corner
// k, (1,0) at the middle of edge k, (1,1) at the centre, (0,1) at the middle of edge k-1.
DomainKey pointKey(const FaceTopology& faces, int face, int sub, double u, double v) {
  auto c = [&](int k) { return faces.corner(face, k); };
  if (sub < 0) {
    if (v == 0.0) return onEdge(c(0), c(1), u);
    if (u == 1.0) return onEdge(c(1), c(2), v);
    if (v == 1.0) return onEdge(c(2), c(3), 1.0 - u);
    if (u == 0.0) return onEdge(c(3), c(0), 1.0 - v);
    return {DomainKey::kInterior, face, -1, 0, u, v};
  }
  if (v == 0.0) return onEdge(c(sub), c(sub + 1), u / 2);
  if (u == 0.0) return onEdge(c(sub - 1), c(sub), 1.0 - v / 2);
  if (u == 1.0) return onSpoke(faces, face, sub, v);
  if (v == 1.0) return onSpoke(faces, face, sub - 1, u);
  return {DomainKey::kInterior, face, sub, 0, u, v};
}

DomainKey lineKey(const FaceTopology& faces, int face, int sub, double u, double v, bool alongU,
                  double& parameter) {
  auto c = [&](int k) { return faces.corner(face, k); };
  const double fixed = alongU ? v : u, moving = alongU ? u : v;
  if (sub < 0) {
    if (alongU && v == 0.0) return edgeLine(c(0), c(1), u, parameter);
    if (!alongU && u == 1.0) return edgeLine(c(1), c(2), v, parameter);
    if (alongU && v == 1.0) return edgeLine(c(2), c(3), 1.0 - u, parameter);
    if (!alongU && u == 0.0) return edgeLine(c(3), c(0), 1.0 - v, parameter);
  } else {
    int n = faces.size(face);
    if (alongU && v == 0.0) return edgeLine(c(sub), c(sub + 1), u / 2, parameter);
    if (!alongU && u == 0.0) return edgeLine(c(sub - 1), c(sub), 1.0 - v / 2, parameter);
    if (!alongU && u == 1.0) {
      parameter = v;
      return {DomainKey::kSpoke, face, sub % n, 0, 0, 0};
    }
    if (alongU && v == 1.0) {
      parameter = u;
      return {DomainKey::kSpoke, face, (sub + n - 1) % n, 0, 0, 0};
    }
  }
  parameter = moving;
  return {DomainKey::kInterior, face, sub, alongU ? 1 : 2, fixed, 0};
}

}  // namespace tessera
