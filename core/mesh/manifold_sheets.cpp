// cutIntoSheets (core/mesh/manifold_sheets.h). Every face corner starts one half-edge; sorting the
// half-edges by their undirected edge puts the faces of each edge side by side, which finds the
// non-manifold edges. The two corners of a vertex on either side of a manifold edge belong to the
// same fan, so joining them in a union-find leaves one set per fan: a manifold vertex has one, a
// bow-tie vertex more, and each fan becomes one vertex of the sheets.
#include "core/mesh/manifold_sheets.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/base/small_vector.h"

namespace tessera {
namespace {

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

// The rest of the cut indexes with these, so a mesh that skipped validation must not get by.
void requireIndexedFaces(const ControlMesh& mesh) {
  const bool sizesValid =
      std::all_of(mesh.faceSizes.begin(), mesh.faceSizes.end(), [](int s) { return s >= 3; });
  const int64_t total = std::accumulate(mesh.faceSizes.begin(), mesh.faceSizes.end(), int64_t{0});
  const bool indexed = sizesValid && total == static_cast<int64_t>(mesh.faceVertices.size()) &&
                       total <= INT_MAX &&
                       std::all_of(mesh.faceVertices.begin(), mesh.faceVertices.end(),
                                   [&](int v) { return v >= 0 && v < mesh.vertexCount(); });
  if (!indexed) {
    throwInvalid("cutIntoSheets needs a mesh that passed validateControlMesh");
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

// What OpenSubdiv's tags read at a vertex: face corners there, Far's edges there (FarEdge), how
// many of those are boundary or non-manifold edges, and how many manifold ones are infinitely
// sharp creases.
struct VertexEdges {
  int corners = 0, edges = 0, boundary = 0, nonManifold = 0, sharpCreases = 0;
};

class SheetCutter {
 public:
  explicit SheetCutter(const ControlMesh& mesh)
      : mesh_(mesh), corners_(mesh), fans_(corners_.count()), around_(mesh.positions.size()) {}
  ManifoldSheets cut();

 private:
  void classifyEdges();
  bool countFarEdges(const HalfEdge* first, const HalfEdge* last);
  void numberSheetVertices(ManifoldSheets& out);
  void countSharpCreases();
  bool sharpened(int vertex) const;
  void tagSheets(ManifoldSheets& out) const;
  void tagSheetCreases(ControlMesh& sheets) const;
  void tagSeams(ManifoldSheets& out) const;

  const ControlMesh& mesh_;
  const FaceCorners corners_;
  DisjointSets fans_;
  std::vector<VertexEdges> around_;
  std::vector<std::pair<int, int>> nonManifoldEdges_;  // (lo, hi)
  std::vector<uint8_t> nonManifoldVertex_;
  std::vector<int> sheetVertex_;  // per fan (its root corner), the sheets' vertex
};

// Far's edges on one vertex pair, as Vtr::Level::completeTopologyFromFaceVertices makes them
// face by face: a corner joins the pair's first edge, which turns non-manifold when the corner
// runs the same way as the edge's first face or comes as its third face; a face that meets the
// edge again gets a new, non-manifold edge; and every degenerate corner (from a vertex to itself)
// is an edge of its own, non-manifold, and listed twice at its vertex. OpenSubdiv's tags count
// these edges (prepareComponentTagsAndSharpness), so the cut counts them the same way.
struct FarEdge {
  int from = 0, lastFace = 0, faces = 1;
  bool nonManifold = false;
};

// Returns whether the pair is one manifold edge: two faces running along it opposite ways.
bool SheetCutter::countFarEdges(const HalfEdge* first, const HalfEdge* last) {
  const int lo = int(first->edge >> 32), hi = int(first->edge & 0xffffffffu);
  if (lo == hi) {
    const int count = int(last - first);
    around_[lo].edges += 2 * count, around_[lo].boundary += 2 * count, around_[lo].nonManifold += 2 * count;
    return false;
  }
  SmallVector<FarEdge, 2> edges;
  for (const HalfEdge* h = first; h != last; ++h) {
    const int face = corners_.face(h->corner), from = corners_.vertex(h->corner);
    if (edges.empty()) {
      edges.push_back({from, face});
      continue;
    }
    FarEdge& shared = edges[0];
    if (shared.lastFace == face) {
      shared.nonManifold = true;
      edges.push_back({from, face, 1, true});
      continue;
    }
    shared.nonManifold |= shared.faces > 1 || from == shared.from;
    ++shared.faces, shared.lastFace = face;
  }
  for (const FarEdge& e : edges) {
    for (int v : {lo, hi}) {
      around_[v].edges += 1;
      around_[v].boundary += e.faces < 2;
      around_[v].nonManifold += e.nonManifold;
    }
  }
  return edges.size() == 1 && edges[0].faces == 2 && !edges[0].nonManifold;
}

// Across a manifold edge its end vertices' corners in the two faces join one fan. A single
// corner is a boundary edge; every other pair is non-manifold.
void SheetCutter::classifyEdges() {
  const std::vector<HalfEdge> halfEdges = sortedHalfEdges(corners_, mesh_.vertexCount());
  const HalfEdge* const end = halfEdges.data() + halfEdges.size();
  for (const HalfEdge* first = halfEdges.data(); first != end;) {
    const HalfEdge* last = first + 1;
    while (last != end && last->edge == first->edge) ++last;
    const int lo = int(first->edge >> 32), hi = int(first->edge & 0xffffffffu);
    const bool boundary = last - first == 1 && lo != hi;
    if (countFarEdges(first, last)) {
      const int a = first[0].corner, b = first[1].corner;
      fans_.join(a, corners_.next(b));
      fans_.join(corners_.next(a), b);
    } else if (!boundary) {
      nonManifoldEdges_.push_back({lo, hi});
    }
    first = last;
  }
}

// Each fan's vertex: the input's own index for the first fan met, a copy after the input's.
void SheetCutter::numberSheetVertices(ManifoldSheets& out) {
  std::vector<uint8_t> taken(mesh_.positions.size(), 0);
  nonManifoldVertex_.assign(mesh_.positions.size(), 0);
  sheetVertex_.assign(corners_.count(), -1);
  out.inputVertex.resize(mesh_.positions.size());
  std::iota(out.inputVertex.begin(), out.inputVertex.end(), 0);
  for (int corner = 0; corner < corners_.count(); ++corner) {
    const int v = corners_.vertex(corner);
    around_[v].corners += 1;
    if (around_[v].nonManifold > 0) nonManifoldVertex_[v] = 1;
    const int root = fans_.find(corner);
    if (sheetVertex_[root] >= 0) continue;
    if (!taken[v]) {
      sheetVertex_[root] = v, taken[v] = 1;
      continue;
    }
    nonManifoldVertex_[v] = 1;
    sheetVertex_[root] = int(out.inputVertex.size());
    out.inputVertex.push_back(v);
  }
  out.sheets.faceVertices.resize(corners_.count());
  for (int c = 0; c < corners_.count(); ++c) out.sheets.faceVertices[c] = sheetVertex_[fans_.find(c)];
  out.nonManifoldEdges = int(nonManifoldEdges_.size());
  out.nonManifoldVertices = int(std::count(nonManifoldVertex_.begin(), nonManifoldVertex_.end(), 1));
}

void SheetCutter::countSharpCreases() {
  for (const CreaseEdge& c : mesh_.creases) {
    const std::pair<int, int> edge{std::min(c.v0, c.v1), std::max(c.v0, c.v1)};
    if (c.sharpness < kInfiniteSharpness || std::binary_search(nonManifoldEdges_.begin(), nonManifoldEdges_.end(), edge)) continue;
    around_[c.v0].sharpCreases += 1, around_[c.v1].sharpCreases += 1;
  }
}

// OpenSubdiv leaves a non-manifold vertex unsharpened only inside an interior non-manifold
// crease: two non-manifold edges, no boundary edge, and more faces than edges (the fins). Its
// rule there comes from its sharp edges: with an infinitely sharp crease besides the two, a
// corner at every level, which the sheets' copies (each fin sees the two edges, one fin the
// crease too) would not all be unless sharpened.
bool SheetCutter::sharpened(int v) const {
  if (!nonManifoldVertex_[v]) return false;
  const VertexEdges& e = around_[v];
  return !(e.nonManifold == 2 && e.boundary == 0 && e.corners > e.edges && e.sharpCreases == 0);
}

// The sheets carry each input vertex's sharpness on every copy, and its creases. Their
// boundaries are the input's boundaries and its cuts, which OpenSubdiv sharpens alike; a sheet
// corner with one face must not be sharpened as a topological corner unless the input's was, so
// the sheets take the edge-only rule and name those corners.
void SheetCutter::tagSheets(ManifoldSheets& out) const {
  ControlMesh& sheets = out.sheets;
  sheets.rules = mesh_.rules;
  sheets.holes = mesh_.holes;
  sheets.uvs = mesh_.uvs;
  sheets.uvIndices = mesh_.uvIndices;
  sheets.origin = mesh_.origin;
  sheets.faceSizes = mesh_.faceSizes;
  sheets.positions.resize(out.inputVertex.size());
  for (size_t s = 0; s < out.inputVertex.size(); ++s) sheets.positions[s] = mesh_.positions[out.inputVertex[s]];

  std::vector<float> sharpness(mesh_.positions.size(), 0.0f);
  for (const CornerVertex& c : mesh_.corners) sharpness[c.vertex] = c.sharpness;
  const bool sharpenCorners = mesh_.rules.boundary == BoundaryInterpolation::kEdgeAndCorner;
  if (sharpenCorners) sheets.rules.boundary = BoundaryInterpolation::kEdgeOnly;
  for (int v = 0; v < mesh_.vertexCount(); ++v) {
    const bool topologicalCorner = around_[v].corners == 1 && around_[v].edges == 2;
    if (sharpened(v) || (sharpenCorners && topologicalCorner)) sharpness[v] = kInfiniteSharpness;
  }
  for (size_t s = 0; s < out.inputVertex.size(); ++s) {
    if (sharpness[out.inputVertex[s]] > 0.0f) sheets.corners.push_back({int(s), sharpness[out.inputVertex[s]]});
  }
  tagSheetCreases(sheets);
}

// Each input crease on the sheet edge it became. A non-manifold edge is usually cut into
// boundaries, but two of its faces that meet elsewhere too share one sheet edge (a two-sided
// face): it stays infinitely sharp.
void SheetCutter::tagSheetCreases(ControlMesh& sheets) const {
  std::vector<std::pair<std::pair<int, int>, float>> creases;  // by input edge (lo, hi)
  for (const CreaseEdge& c : mesh_.creases) creases.push_back({{std::min(c.v0, c.v1), std::max(c.v0, c.v1)}, c.sharpness});
  std::sort(creases.begin(), creases.end());
  std::set<std::pair<int, int>> added;
  for (int c = 0; c < corners_.count(); ++c) {
    const int a = corners_.vertex(c), b = corners_.vertex(corners_.next(c));
    const std::pair<int, int> edge{std::min(a, b), std::max(a, b)};
    const bool nonManifold = std::binary_search(nonManifoldEdges_.begin(), nonManifoldEdges_.end(), edge);
    const auto found = std::lower_bound(creases.begin(), creases.end(), std::pair{edge, -1.0f});
    const bool creased = found != creases.end() && found->first == edge;
    if (!nonManifold && !creased) continue;
    const int sa = sheets.faceVertices[c], sb = sheets.faceVertices[corners_.next(c)];
    const std::pair<int, int> sheetEdge{std::min(sa, sb), std::max(sa, sb)};
    if (!added.insert(sheetEdge).second) continue;
    if (nonManifold) {
      sheets.creases.push_back({sheetEdge.first, sheetEdge.second, kInfiniteSharpness});
      continue;
    }
    for (auto it = found; it != creases.end() && it->first == edge; ++it) {
      sheets.creases.push_back({sheetEdge.first, sheetEdge.second, it->second});
    }
  }
}

void SheetCutter::tagSeams(ManifoldSheets& out) const {
  out.seams = mesh_;
  for (const auto& [lo, hi] : nonManifoldEdges_) out.seams.creases.push_back({lo, hi, kInfiniteSharpness});
  for (int v = 0; v < mesh_.vertexCount(); ++v) {
    if (sharpened(v)) out.seams.corners.push_back({v, kInfiniteSharpness});
  }
}

ManifoldSheets SheetCutter::cut() {
  ManifoldSheets out;
  classifyEdges();
  countSharpCreases();
  numberSheetVertices(out);
  if (!out.cut()) return ManifoldSheets{};
  if (mesh_.rules.boundary == BoundaryInterpolation::kNone) {
    throwUnsupported("the mesh has " + std::to_string(out.nonManifoldEdges) + " non-manifold edges and " +
                     std::to_string(out.nonManifoldVertices) +
                     " non-manifold vertices, which are supported only with a boundary rule other than "
                     "\"none\" (t interpolateboundary 1 or 2)");
  }
  tagSheets(out);
  tagSeams(out);
  return out;
}

}  // namespace

ManifoldSheets cutIntoSheets(const ControlMesh& mesh) {
  requireIndexedFaces(mesh);
  return SheetCutter(mesh).cut();
}

}  // namespace tessera
