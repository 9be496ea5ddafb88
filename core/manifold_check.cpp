// requireManifold (core/manifold_check.h). Every face corner starts one half-edge; sorting the
// half-edges by their undirected edge puts the faces of each edge side by side, which finds edges
// with more than two faces and pairs traversed the same way. The two corners of a vertex on either
// side of a shared edge belong to the same fan, so joining them in a union-find leaves one set per
// fan: a manifold vertex has one, a bow-tie vertex more.
#include "core/manifold_check.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "core/error.h"

namespace tessera {
namespace {

const char* const kRefusal = "; non-manifold topology is not supported";

// Walks the flat face arrays by corner, a corner being an index into faceVertices.
class FaceCorners {
 public:
  explicit FaceCorners(const ControlMesh& mesh)
      : vertices_(mesh.faceVertices), faceOf_(mesh.faceVertices.size()) {
    faceStart_.reserve(mesh.faceSizes.size() + 1);
    int start = 0;
    for (int face = 0; face < mesh.faceCount(); ++face) {
      faceStart_.push_back(start);
      std::fill_n(faceOf_.begin() + start, mesh.faceSizes[face], face);
      start += mesh.faceSizes[face];
    }
    faceStart_.push_back(start);
  }

  int count() const { return static_cast<int>(vertices_.size()); }
  int vertex(int corner) const { return vertices_[corner]; }
  int face(int corner) const { return faceOf_[corner]; }
  int next(int corner) const {
    const int face = faceOf_[corner];
    return corner + 1 == faceStart_[face + 1] ? faceStart_[face] : corner + 1;
  }

 private:
  const std::vector<int>& vertices_;
  std::vector<int> faceOf_;
  std::vector<int> faceStart_;
};

class DisjointSets {
 public:
  explicit DisjointSets(int count) : parent_(count) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int find(int x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];  // path halving
      x = parent_[x];
    }
    return x;
  }
  void join(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

struct HalfEdge {
  uint64_t edge;  // undirected: lower vertex in the high word
  int corner;     // where the half-edge starts
};

std::string edgeText(uint64_t edge) {
  std::string text = "(";  // appended: `"(" + std::string` trips GCC 12's -Wrestrict (105651)
  text += std::to_string(edge >> 32);
  text += ", ";
  text += std::to_string(edge & 0xffffffffu);
  text += ')';
  return text;
}

// The rest of the check indexes with these, so a mesh that skipped validation must not get by.
void requireIndexedFaces(const ControlMesh& mesh) {
  const bool sizesValid =
      std::all_of(mesh.faceSizes.begin(), mesh.faceSizes.end(), [](int s) { return s >= 3; });
  const int64_t total = std::accumulate(mesh.faceSizes.begin(), mesh.faceSizes.end(), int64_t{0});
  const bool indexed = sizesValid && total == static_cast<int64_t>(mesh.faceVertices.size()) &&
                       total <= INT_MAX &&
                       std::all_of(mesh.faceVertices.begin(), mesh.faceVertices.end(),
                                   [&](int v) { return v >= 0 && v < mesh.vertexCount(); });
  if (!indexed) {
    throwInvalid("requireManifold needs a mesh that passed validateControlMesh");
  }
}

// Ordered by edge, then corner. A counting sort on the lower vertex does most of the work in
// linear time; each vertex's bucket, about as long as its valence, is then sorted on its own.
// (One std::sort of all half-edges took 14 times as long as validateControlMesh on a 1M-quad grid.)
std::vector<HalfEdge> sortedHalfEdges(const FaceCorners& corners, int vertexCount) {
  std::vector<int> bucketStart(static_cast<size_t>(vertexCount) + 1, 0);
  for (int corner = 0; corner < corners.count(); ++corner) {
    const int a = corners.vertex(corner), b = corners.vertex(corners.next(corner));
    ++bucketStart[std::min(a, b) + 1];
  }
  for (int v = 0; v < vertexCount; ++v) bucketStart[v + 1] += bucketStart[v];
  std::vector<int> fill(bucketStart.begin(), bucketStart.end() - 1);
  std::vector<HalfEdge> halfEdges(corners.count());
  for (int corner = 0; corner < corners.count(); ++corner) {
    const auto a = static_cast<uint32_t>(corners.vertex(corner));
    const auto b = static_cast<uint32_t>(corners.vertex(corners.next(corner)));
    const uint32_t low = std::min(a, b);
    halfEdges[fill[low]++] = {(uint64_t{low} << 32) | std::max(a, b), corner};
  }
  for (int v = 0; v < vertexCount; ++v) {
    std::sort(halfEdges.begin() + bucketStart[v], halfEdges.begin() + bucketStart[v + 1],
              [](const HalfEdge& x, const HalfEdge& y) {
                return x.edge != y.edge ? x.edge < y.edge : x.corner < y.corner;
              });
  }
  return halfEdges;
}

[[noreturn]] void refuseSharedEdge(const HalfEdge* first, const HalfEdge* last,
                                   const FaceCorners& corners) {
  constexpr long kMaxListed = 8;
  std::string faces;
  for (const HalfEdge* h = first; h != last && h - first < kMaxListed; ++h) {
    faces += (h == first ? "" : ", ") + std::to_string(corners.face(h->corner));
  }
  if (last - first > kMaxListed) faces += ", ...";
  throwUnsupported("non-manifold edge " + edgeText(first->edge) + " is shared by " +
                   std::to_string(last - first) + " faces (" + faces + ")" + kRefusal);
}

// Two faces on one edge: they must run along it in opposite directions, and each end vertex's
// corners in the two faces are then neighbours in that vertex's fan.
void pairAcrossEdge(const HalfEdge& one, const HalfEdge& other, const FaceCorners& corners,
                    DisjointSets& fans) {
  const int a = one.corner, b = other.corner;
  if (corners.vertex(a) == corners.vertex(b)) {
    throwUnsupported("faces " + std::to_string(corners.face(a)) + " and " +
                     std::to_string(corners.face(b)) + " both traverse edge " + edgeText(one.edge) +
                     " from vertex " + std::to_string(corners.vertex(a)) + " to vertex " +
                     std::to_string(corners.vertex(corners.next(a))) +
                     "; inconsistently oriented faces are not supported");
  }
  fans.join(a, corners.next(b));
  fans.join(corners.next(a), b);
}

void checkEdges(const FaceCorners& corners, int vertexCount, DisjointSets& fans) {
  const std::vector<HalfEdge> halfEdges = sortedHalfEdges(corners, vertexCount);
  const HalfEdge* const end = halfEdges.data() + halfEdges.size();
  for (const HalfEdge* first = halfEdges.data(); first != end;) {
    const HalfEdge* last = first + 1;
    while (last != end && last->edge == first->edge) ++last;
    if (last - first > 2) refuseSharedEdge(first, last, corners);
    if (last - first == 2) pairAcrossEdge(first[0], first[1], corners, fans);
    first = last;
  }
}

void checkFans(const ControlMesh& mesh, const FaceCorners& corners, DisjointSets& fans) {
  std::vector<int> fanFace(mesh.positions.size(), -1);  // a face of the first fan found
  for (int corner = 0; corner < corners.count(); ++corner) {
    if (fans.find(corner) != corner) continue;
    const int vertex = corners.vertex(corner);
    if (fanFace[vertex] >= 0) {
      throwUnsupported("vertex " + std::to_string(vertex) +
                       " is a bow-tie: its faces form more than one fan (faces " +
                       std::to_string(fanFace[vertex]) + " and " +
                       std::to_string(corners.face(corner)) +
                       " are not connected through edges around it)" + kRefusal);
    }
    fanFace[vertex] = corners.face(corner);
  }
}

}  // namespace

void requireManifold(const ControlMesh& mesh) {
  requireIndexedFaces(mesh);
  const FaceCorners corners(mesh);
  DisjointSets fans(corners.count());
  checkEdges(corners, mesh.vertexCount(), fans);
  checkFans(mesh, corners, fans);
}

}  // namespace tessera
