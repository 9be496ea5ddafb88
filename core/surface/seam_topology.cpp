#include "core/surface/seam_topology.h"

#include <algorithm>
#include <climits>
#include <map>
#include <numeric>
#include <span>

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
  // Each edge's faces, in face order: (edge, face) pairs sorted by edge, then face.
  std::vector<std::pair<std::pair<int, int>, int>> edgeFaceList;
  for (int f = 0; f < int(faceSizes.size()); ++f) {
    if (hole[f]) continue;
    for (int k = 0; k < faceSizes[f]; ++k) edgeFaceList.push_back({ordered(corner(f, k), corner(f, k + 1)), f});
  }
  std::sort(edgeFaceList.begin(), edgeFaceList.end());
  auto edgeFaces = [&edgeFaceList](int a, int b) {
    const std::pair<int, int> edge = ordered(a, b);
    const auto first = std::lower_bound(edgeFaceList.begin(), edgeFaceList.end(), std::pair{edge, INT_MIN});
    auto last = first;
    while (last != edgeFaceList.end() && last->first == edge) ++last;
    return std::span(first, last);
  };
  cornerPinched.assign(faceVertices.size(), 0);
  for (int f = 0; f < int(faceSizes.size()); ++f) {
    if (hole[f]) continue;
    for (int k = 0; k < faceSizes[f]; ++k) {
      auto other = [&](int a, int b) {
        for (const auto& [edge, g] : edgeFaces(a, b)) {
          if (g != f) return g;
        }
        return -1;
      };
      const int before = other(corner(f, k - 1), corner(f, k)), after = other(corner(f, k), corner(f, k + 1));
      const bool manifold = edgeFaces(corner(f, k - 1), corner(f, k)).size() == 2 &&
                            edgeFaces(corner(f, k), corner(f, k + 1)).size() == 2;
      // The face itself folds there: it comes back along the edge it left by (a → v → a), or an
      // edge there has collapsed to the vertex (v → v); its sides there are one curve or a point.
      const bool folded = corner(f, k - 1) == corner(f, k + 1) || corner(f, k - 1) == corner(f, k) ||
                          corner(f, k) == corner(f, k + 1);
      cornerPinched[faceOffsets[f] + k] = (manifold && before >= 0 && before == after) || folded;
    }
  }
  std::vector<int> parent(faceSizes.size());
  cornerWedge.assign(faceVertices.size(), -1);
  // Each vertex's faces, in face order (a face as often as it has the vertex as a corner).
  std::vector<std::pair<int, int>> vertexFaceList;
  for (int f = 0; f < int(faceSizes.size()); ++f) {
    if (hole[f]) continue;
    for (int k = 0; k < faceSizes[f]; ++k) vertexFaceList.push_back({corner(f, k), f});
  }
  std::sort(vertexFaceList.begin(), vertexFaceList.end());
  std::vector<int> faces;
  for (size_t at = 0; at < vertexFaceList.size();) {
    const int v = vertexFaceList[at].first;
    faces.clear();
    for (; at < vertexFaceList.size() && vertexFaceList[at].first == v; ++at) faces.push_back(vertexFaceList[at].second);
    for (int f : faces) parent[f] = f;
    bool split = false;
    for (int f : faces) {
      for (int k = 0; k < faceSizes[f]; ++k) {
        if (corner(f, k) != v) continue;
        for (int w : {corner(f, k + 1), corner(f, k - 1)}) {
          const auto shared = edgeFaces(v, w);
          if (sharpCorner[v] || sharp(v, w)) {
            split |= shared.size() > 1 || sharpCorner[v];
            continue;
          }
          for (const auto& [edge, g] : shared) parent[findRoot(parent, g)] = findRoot(parent, f);
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

size_t SeamTopology::bytes() const {
  auto bytesOf = [](const auto& v) { return v.size() * sizeof(v[0]); };
  return bytesOf(faceSizes) + bytesOf(faceVertices) + bytesOf(faceOffsets) + bytesOf(sharpEdges) +
         bytesOf(cornerWedge) + bytesOf(cornerPinched);
}

bool SeamTopology::sharp(int v0, int v1) const {
  return std::binary_search(sharpEdges.begin(), sharpEdges.end(), ordered(v0, v1));
}

SideLine rootSideLine(const SeamTopology& topology, int face, int sub, int side) {
  auto c = [&](int k) { return topology.corner(face, k); };
  // The base edge (from → to) a side runs along: t from `from` is origin + sign·s/halves.
  auto onEdge = [&](int from, int to, int origin, int sign, int halves) {
    SideLine line;
    const auto [lo, hi] = ordered(from, to);
    line.line = {SeamLine::kEdge, lo, hi};
    // Measured from the lower vertex instead: t' = 1 − t.
    line.origin = from < to ? origin : 1 - origin;
    line.sign = from < to ? sign : -sign;
    line.halves = halves;
    line.sharp = topology.sharp(from, to);
    return line;
  };
  auto onSpoke = [&](int k) {
    const int n = topology.faceSizes[face];
    SideLine line;
    line.line = {SeamLine::kSpoke, face, ((k % n) + n) % n};
    return line;
  };
  if (sub < 0) {
    switch (side) {
      case 0: return onEdge(c(0), c(1), 0, 1, 1);    // t = u
      case 1: return onEdge(c(1), c(2), 0, 1, 1);    // t = v
      case 2: return onEdge(c(2), c(3), 1, -1, 1);   // t = 1 − u
      default: return onEdge(c(3), c(0), 1, -1, 1);  // t = 1 − v
    }
  }
  switch (side) {
    case 0: return onEdge(c(sub), c(sub + 1), 0, 1, 2);   // t = u/2
    case 1: return onSpoke(sub);                          // t = v
    case 2: return onSpoke(sub - 1);                      // t = u
    default: return onEdge(c(sub - 1), c(sub), 1, -1, 2);  // t = 1 − v/2
  }
}

}  // namespace tessera
