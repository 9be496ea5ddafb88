#include "core/output/uv_seams.h"

#include <algorithm>
#include <cstdint>
#include <numeric>

#include <stdexcept>

namespace tessera {

namespace {

// What a corner's UV belongs to at its vertex: the face's inside (a vertex there is only that
// face's), one UV edge (two control vertices' UV indices, lower vertex first: faces that share
// the edge and both its UVs are continuous across it), or one control UV (at a control vertex).
// Corners of one vertex with the same key get one UV; different keys are a seam.
struct CornerKey {
  enum Kind : uint8_t { kInside, kEdge, kCorner } kind;
  int a, b;
  friend bool operator==(const CornerKey&, const CornerKey&) = default;
};

class FaceCorners {
 public:
  explicit FaceCorners(const ControlMesh& mesh) : mesh_(mesh), first_(mesh.faceCount() + 1, 0) {
    for (int f = 0; f < mesh.faceCount(); ++f) first_[f + 1] = first_[f] + mesh.faceSizes[f];
  }
  int size(int face) const { return mesh_.faceSizes[face]; }
  int vertex(int face, int k) const { return mesh_.faceVertices[first_[face] + k]; }
  int uv(int face, int k) const { return mesh_.uvIndices[first_[face] + k]; }

  CornerKey corner(int face, int k) const { return {CornerKey::kCorner, uv(face, k), 0}; }
  CornerKey edge(int face, int k) const {
    const int next = (k + 1) % size(face);
    return vertex(face, k) < vertex(face, next) ? CornerKey{CornerKey::kEdge, uv(face, k), uv(face, next)}
                                                : CornerKey{CornerKey::kEdge, uv(face, next), uv(face, k)};
  }

 private:
  const ControlMesh& mesh_;
  std::vector<int> first_;
};

// Where (u, v) of a root lies in its base face (Bfr's parameterization: a quad's corners 0..3 at
// (0,0), (1,0), (1,1), (0,1); an n-gon's sub-face k with corner k at its origin, edge k along
// v = 0 and edge k − 1 along u = 0, its other two sides inside the face).
CornerKey keyOf(const FaceCorners& faces, int face, int subFace, double u, double v) {
  if (subFace < 0) {
    static constexpr int kCornerAt[2][2] = {{0, 3}, {1, 2}};  // [u == 1][v == 1]
    const bool uEnd = u == 0 || u == 1, vEnd = v == 0 || v == 1;
    if (uEnd && vEnd) return faces.corner(face, kCornerAt[u == 1][v == 1]);
    if (vEnd) return faces.edge(face, v == 0 ? 0 : 2);
    if (uEnd) return faces.edge(face, u == 1 ? 1 : 3);
    return {CornerKey::kInside, face, 0};
  }
  const int n = faces.size(face);
  if (u == 0 && v == 0) return faces.corner(face, subFace);
  if (v == 0) return faces.edge(face, subFace);
  if (u == 0) return faces.edge(face, (subFace + n - 1) % n);
  return {CornerKey::kInside, face, 0};
}

template <typename T>
void repeat(std::vector<T>& values, size_t per, const std::vector<uint32_t>& sources) {
  if (values.empty()) return;
  values.reserve(values.size() + per * sources.size());  // the copies read the vector they grow
  for (uint32_t s : sources) {
    for (size_t c = 0; c < per; ++c) values.push_back(values[per * s + c]);
  }
}

}  // namespace

void attachUvs(const ControlMesh& control, const LimitUvs& uvs, const std::vector<UvQuery>& corners, TriangleMesh& mesh,
               const std::function<void()>& checkpoint) {
  if (corners.size() != mesh.indices.size()) throw std::logic_error("attachUvs: one parameter per triangle corner is needed");
  const FaceCorners faces(control);
  // Each output vertex (a vertex, or its seam copy) with its key, chained per vertex; the UV is
  // evaluated once per output vertex, at the first corner that made it.
  const size_t vertices = mesh.positions.size();
  constexpr uint32_t kNone = UINT32_MAX;
  std::vector<CornerKey> key(vertices);
  std::vector<uint32_t> next(vertices, kNone), copiedFrom;  // copiedFrom: per seam copy, its vertex
  std::vector<uint8_t> used(vertices, 0);
  std::vector<UvQuery> queries(vertices);
  for (size_t c = 0; c < corners.size(); ++c) {
    if (checkpoint && (c & 0xffff) == 0) checkpoint();
    const uint32_t w = mesh.indices[c];
    const UvQuery& q = corners[c];
    const CornerKey k = keyOf(faces, q.face, q.subFace, q.u, q.v);
    if (!used[w]) {
      used[w] = 1, key[w] = k, queries[w] = q;
      continue;
    }
    uint32_t target = w;
    while (!(key[target] == k) && next[target] != kNone) target = next[target];
    if (!(key[target] == k)) {
      const uint32_t copy = uint32_t(key.size());
      next[target] = copy;
      key.push_back(k), next.push_back(kNone), queries.push_back(q), copiedFrom.push_back(w);
      target = copy;
    }
    mesh.indices[c] = target;
  }
  const std::vector<std::array<float, 2>> values = uvs.evaluate(queries, checkpoint);
  if (checkpoint) checkpoint();
  mesh.uvs.resize(2 * values.size());
  for (size_t v = 0; v < values.size(); ++v) mesh.uvs[2 * v] = values[v][0], mesh.uvs[2 * v + 1] = values[v][1];
  // Seam copies repeat their vertex bit for bit (and point back to it, as crease copies do).
  repeat(mesh.positions, 1, copiedFrom);
  repeat(mesh.normals, 1, copiedFrom);
  repeat(mesh.vertexFace, 1, copiedFrom);
  repeat(mesh.vertexSubFace, 1, copiedFrom);
  repeat(mesh.vertexUv, 2, copiedFrom);
  if (copiedFrom.empty()) return;
  if (mesh.vertexPoint.empty()) {  // the uniform path has no crease copies: each vertex is its own point
    mesh.vertexPoint.resize(vertices);
    std::iota(mesh.vertexPoint.begin(), mesh.vertexPoint.end(), 0u);
  }
  for (uint32_t s : copiedFrom) mesh.vertexPoint.push_back(mesh.vertexPoint[s]);
}

}  // namespace tessera
