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

// Items bucketed by a key in [0, keys) (a counting sort, stable: within a bucket, in the order
// given): `first[key]` .. `first[key + 1]` index `items`.
struct Buckets {
  std::vector<int> first, items;
  template <class KeyOf>
  Buckets(int keys, int count, KeyOf keyOf) : first(size_t(keys) + 1, 0), items(size_t(count)) {
    for (int i = 0; i < count; ++i) {
      if (const int key = keyOf(i); key >= 0) ++first[size_t(key) + 1];
    }
    std::inclusive_scan(first.begin(), first.end(), first.begin());
    std::vector<int> at(first.begin(), first.end() - 1);
    for (int i = 0; i < count; ++i) {
      if (const int key = keyOf(i); key >= 0) items[size_t(at[size_t(key)]++)] = i;
    }
    items.resize(size_t(first.back()));
  }
  std::span<const int> of(int key) const {
    return {items.data() + first[size_t(key)], items.data() + first[size_t(key) + 1]};
  }
};

// The faces on each edge (holes left out), found from any face corner whose edge (corner k to
// k + 1) it is: a face as often as it has the edge, in face order.
class EdgeFaces {
 public:
  EdgeFaces(const SeamTopology& t, const std::vector<int>& cornerFace, const std::vector<uint8_t>& hole,
            int vertices) {
    const int corners = int(cornerFace.size());
    auto edgeOf = [&](int c) {
      const int f = cornerFace[size_t(c)], k = c - t.faceOffsets[size_t(f)];
      return ordered(t.corner(f, k), t.corner(f, k + 1));
    };
    // By the edge's lower vertex (in corner order, so in face order), then by its upper one.
    const Buckets byLow(vertices, corners, [&](int c) {
      return hole[size_t(cornerFace[size_t(c)])] ? -1 : edgeOf(c).first;
    });
    faces_.reserve(byLow.items.size());
    first_.assign(size_t(corners), 0);
    last_.assign(size_t(corners), 0);
    std::vector<int> group;
    for (int v = 0; v < vertices; ++v) {
      group.assign(byLow.of(v).begin(), byLow.of(v).end());
      std::stable_sort(group.begin(), group.end(), [&](int a, int b) { return edgeOf(a).second < edgeOf(b).second; });
      for (size_t i = 0; i < group.size();) {
        size_t j = i;
        while (j < group.size() && edgeOf(group[j]).second == edgeOf(group[i]).second) ++j;
        const int from = int(faces_.size());
        for (size_t m = i; m < j; ++m) faces_.push_back(cornerFace[size_t(group[m])]);
        for (size_t m = i; m < j; ++m) first_[size_t(group[m])] = from, last_[size_t(group[m])] = int(faces_.size());
        i = j;
      }
    }
  }
  std::span<const int> ofCorner(int c) const {
    return {faces_.data() + first_[size_t(c)], faces_.data() + last_[size_t(c)]};
  }

 private:
  std::vector<int> faces_, first_, last_;
};

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
  const int corners = int(faceVertices.size());
  std::vector<int> cornerFace(static_cast<size_t>(corners));
  for (int f = 0; f < int(faceSizes.size()); ++f) {
    std::fill_n(cornerFace.begin() + faceOffsets[f], faceSizes[f], f);
  }
  const EdgeFaces edgeFaces(*this, cornerFace, hole, mesh.vertexCount());
  // Corner k's edges: to corner k + 1 (its own) and from corner k − 1 (the one before).
  auto before = [&](int f, int k) { return faceOffsets[f] + (k + faceSizes[f] - 1) % faceSizes[f]; };
  cornerPinched.assign(faceVertices.size(), 0);
  for (int f = 0; f < int(faceSizes.size()); ++f) {
    if (hole[f]) continue;
    for (int k = 0; k < faceSizes[f]; ++k) {
      auto other = [&](std::span<const int> shared) {
        for (int g : shared) {
          if (g != f) return g;
        }
        return -1;
      };
      const std::span<const int> in = edgeFaces.ofCorner(before(f, k)), out = edgeFaces.ofCorner(faceOffsets[f] + k);
      const bool manifold = in.size() == 2 && out.size() == 2;
      // The face itself folds there: it comes back along the edge it left by (a → v → a), or an
      // edge there has collapsed to the vertex (v → v); its sides there are one curve or a point.
      const bool folded = corner(f, k - 1) == corner(f, k + 1) || corner(f, k - 1) == corner(f, k) ||
                          corner(f, k) == corner(f, k + 1);
      const int g = other(in);
      cornerPinched[faceOffsets[f] + k] = (manifold && g >= 0 && g == other(out)) || folded;
    }
  }
  std::vector<int> parent(faceSizes.size());
  cornerWedge.assign(faceVertices.size(), -1);
  // Each vertex's face corners, in face order.
  const Buckets vertexCorners(mesh.vertexCount(), corners, [&](int c) {
    return hole[size_t(cornerFace[size_t(c)])] ? -1 : faceVertices[size_t(c)];
  });
  for (int v = 0; v < mesh.vertexCount(); ++v) {
    const std::span<const int> at = vertexCorners.of(v);
    if (at.empty()) continue;
    for (int c : at) parent[size_t(cornerFace[size_t(c)])] = cornerFace[size_t(c)];
    bool split = false;
    for (int c : at) {
      const int f = cornerFace[size_t(c)], k = c - faceOffsets[f];
      for (const auto& [edge, w] : {std::pair{c, corner(f, k + 1)}, std::pair{before(f, k), corner(f, k - 1)}}) {
        const std::span<const int> shared = edgeFaces.ofCorner(edge);
        if (sharpCorner[v] || sharp(v, w)) {
          split |= shared.size() > 1 || sharpCorner[v];
          continue;
        }
        for (int g : shared) parent[size_t(findRoot(parent, g))] = findRoot(parent, f);
      }
    }
    if (!split) continue;
    std::map<int, int> smallest;
    for (int c : at) {
      const int f = cornerFace[size_t(c)], r = findRoot(parent, f);
      smallest.try_emplace(r, f);
      smallest[r] = std::min(smallest[r], f);
    }
    if (smallest.size() < 2) continue;
    for (int c : at) cornerWedge[size_t(c)] = smallest[findRoot(parent, cornerFace[size_t(c)])];
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
