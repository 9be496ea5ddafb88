#include "core/seam_topology.h"

#include <algorithm>
#include <map>
#include <numeric>

namespace tessera {

namespace {

std::pair<int, int> ordered(int a, int b) { return a < b ? std::pair{a, b} : std::pair{b, a}; }

int findRoot(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

// Wedges: around each base vertex, faces that share an edge at it which is not infinitely sharp
// are one wedge (union-find); an infinitely sharp corner splits every face. A vertex with a single
// wedge (a smooth vertex, a dart, a boundary vertex without interior creases) needs one normal.
SeamTopology::SeamTopology(const ControlMesh& mesh)
    : faceSizes(mesh.faceSizes), faceVertices(mesh.faceVertices) {
  faceOffsets.resize(faceSizes.size());
  std::exclusive_scan(faceSizes.begin(), faceSizes.end(), faceOffsets.begin(), 0);
  for (const CreaseEdge& c : mesh.creases) {
    if (c.sharpness >= kInfiniteSharpness) sharpEdges.push_back(ordered(c.v0, c.v1));
  }
  std::sort(sharpEdges.begin(), sharpEdges.end());
  std::vector<uint8_t> sharpCorner(mesh.vertexCount(), 0), hole(mesh.faceCount(), 0);
  for (const CornerVertex& c : mesh.corners) {
    if (c.sharpness >= kInfiniteSharpness) sharpCorner[c.vertex] = 1;
  }
  for (int f : mesh.holes) hole[f] = 1;
  // Faces at each (vertex, edge): the edge's faces as seen from that vertex.
  std::map<std::pair<int, int>, std::vector<int>> edgeFaces;
  for (int f = 0; f < int(faceSizes.size()); ++f) {
    if (hole[f]) continue;
    for (int k = 0; k < faceSizes[f]; ++k) edgeFaces[ordered(corner(f, k), corner(f, k + 1))].push_back(f);
  }
  std::vector<int> parent(faceSizes.size());
  cornerWedge.assign(faceVertices.size(), -1);
  std::map<int, std::vector<int>> vertexFaces;
  for (int f = 0; f < int(faceSizes.size()); ++f) {
    if (hole[f]) continue;
    for (int k = 0; k < faceSizes[f]; ++k) vertexFaces[corner(f, k)].push_back(f);
  }
  for (const auto& [v, faces] : vertexFaces) {
    for (int f : faces) parent[f] = f;
    bool split = false;
    for (int f : faces) {
      for (int k = 0; k < faceSizes[f]; ++k) {
        if (corner(f, k) != v) continue;
        for (int w : {corner(f, k + 1), corner(f, k - 1)}) {
          const auto& shared = edgeFaces[ordered(v, w)];
          if (sharpCorner[v] || sharp(v, w)) {
            split |= shared.size() > 1 || sharpCorner[v];
            continue;
          }
          for (int g : shared) parent[findRoot(parent, g)] = findRoot(parent, f);
        }
      }
    }
    if (!split) continue;
    std::map<int, int> smallest;
    for (int f : faces) {
      const int r = findRoot(parent, f);
      smallest.try_emplace(r, f);
      smallest[r] = std::min(smallest[r], f);
    }
    if (smallest.size() < 2) continue;
    for (int f : faces) {
      for (int k = 0; k < faceSizes[f]; ++k) {
        if (corner(f, k) == v) cornerWedge[faceOffsets[f] + k] = smallest[findRoot(parent, f)];
      }
    }
  }
}

bool SeamTopology::sharp(int v0, int v1) const {
  return std::binary_search(sharpEdges.begin(), sharpEdges.end(), ordered(v0, v1));
}

namespace {

const Fraction kZero{0, 1}, kOne{1, 1}, kHalf{1, 2};

// A point at `fromA` along base edge (a → b), named from its lower vertex.
PointKey edgePoint(int a, int b, const Fraction& fromA) {
  const Fraction t = a < b ? fromA : kOne - fromA;
  const auto [lo, hi] = ordered(a, b);
  if (t == kZero) return {PointKey::kVertex, lo, 0, {}, {}};
  if (t == kOne) return {PointKey::kVertex, hi, 0, {}, {}};
  return {PointKey::kEdge, lo, hi, t, {}};
}

PointKey spokePoint(const SeamTopology& topology, int face, int spoke, const Fraction& t) {
  const int n = topology.faceSizes[face];
  spoke = ((spoke % n) + n) % n;
  if (t == kOne) return {PointKey::kCenter, face, 0, {}, {}};
  if (t == kZero) return edgePoint(topology.corner(face, spoke), topology.corner(face, spoke + 1), kHalf);
  return {PointKey::kSpoke, face, spoke, t, {}};
}

}  // namespace

PointKey rootPointKey(const SeamTopology& topology, int face, int sub, const Fraction& u, const Fraction& v) {
  auto c = [&](int k) { return topology.corner(face, k); };
  if (sub < 0) {
    if (v == kZero) return edgePoint(c(0), c(1), u);
    if (u == kOne) return edgePoint(c(1), c(2), v);
    if (v == kOne) return edgePoint(c(2), c(3), kOne - u);
    if (u == kZero) return edgePoint(c(3), c(0), kOne - v);
    return {PointKey::kInterior, face, -1, u, v};
  }
  if (v == kZero) return edgePoint(c(sub), c(sub + 1), u.over(2));
  if (u == kZero) return edgePoint(c(sub - 1), c(sub), kOne - v.over(2));
  if (u == kOne) return spokePoint(topology, face, sub, v);
  if (v == kOne) return spokePoint(topology, face, sub - 1, u);
  return {PointKey::kInterior, face, sub, u, v};
}

SideLine rootSideLine(const SeamTopology& topology, int face, int sub, int side) {
  auto c = [&](int k) { return topology.corner(face, k); };
  // The base edge (from → to) a side runs along, and where on it the side's s = 0 and s = 1 lie.
  auto onEdge = [&](int from, int to, const Fraction& t0, int scaleNum, int scaleDen) {
    SideLine line;
    const auto [lo, hi] = ordered(from, to);
    line.line = {LineKey::kEdge, 0, lo, hi, {}};
    // t measured from `from`; flip to the lower vertex.
    line.origin = from < to ? t0 : kOne - t0;
    line.scaleNum = from < to ? scaleNum : -scaleNum;
    line.scaleDen = scaleDen;
    line.sharp = topology.sharp(from, to);
    return line;
  };
  auto onSpoke = [&](int k) {
    const int n = topology.faceSizes[face];
    SideLine line;
    line.line = {LineKey::kSpoke, 0, face, ((k % n) + n) % n, {}};
    line.origin = kZero;
    return line;
  };
  if (sub < 0) {
    switch (side) {
      case 0: return onEdge(c(0), c(1), kZero, 1, 1);    // t = u
      case 1: return onEdge(c(1), c(2), kZero, 1, 1);    // t = v
      case 2: return onEdge(c(2), c(3), kOne, -1, 1);    // t = 1 − u
      default: return onEdge(c(3), c(0), kOne, -1, 1);   // t = 1 − v
    }
  }
  switch (side) {
    case 0: return onEdge(c(sub), c(sub + 1), kZero, 1, 2);   // t = u/2
    case 1: return onSpoke(sub);                              // t = v
    case 2: return onSpoke(sub - 1);                          // t = u
    default: return onEdge(c(sub - 1), c(sub), kOne, -1, 2);  // t = 1 − v/2
  }
}

PointKey linePointKey(const SeamTopology& topology, const LineKey& line, const Fraction& t, int face, int sub) {
  switch (line.kind) {
    case LineKey::kEdge: return edgePoint(line.a, line.b, t);
    case LineKey::kSpoke: return spokePoint(topology, line.a, line.b, t);
    default:
      return line.axis == 0 ? rootPointKey(topology, face, sub, line.fixed, t)
                            : rootPointKey(topology, face, sub, t, line.fixed);
  }
}

NormalSplit normalSplitAt(const SeamTopology& topology, int face, int sub, const Fraction& u, const Fraction& v,
                          int& qualifier) {
  qualifier = -1;
  const PointKey key = rootPointKey(topology, face, sub, u, v);
  if (key.kind == PointKey::kVertex) {
    const int n = topology.faceSizes[face];
    for (int k = 0; k < n; ++k) {
      if (topology.corner(face, k) == key.a) qualifier = topology.wedge(face, k);
    }
    return qualifier < 0 ? NormalSplit::kNone : NormalSplit::kByWedge;
  }
  if (key.kind == PointKey::kEdge && topology.sharp(key.a, key.b)) {
    qualifier = face;
    return NormalSplit::kByFace;
  }
  return NormalSplit::kNone;
}

}  // namespace tessera
