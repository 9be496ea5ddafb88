// validateControlMesh (declared in core/mesh/control_mesh.h): the invariants the rest of core/ relies
// on, checked in an order where each check may assume the earlier ones (sizes before indices,
// indices before edges). Every pass is linear in the mesh size, apart from sorts of the crease
// and corner tags.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include "core/mesh/control_mesh.h"

#include "core/base/error.h"

namespace tessera {
namespace {

std::string formatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void checkCounts(const ControlMesh& mesh, const MeshLimits& limits) {
  if (static_cast<int64_t>(mesh.positions.size()) > limits.maxVertices) {
    throwLimit("the mesh has " + std::to_string(mesh.positions.size()) +
               " vertices; the limit is " + std::to_string(limits.maxVertices));
  }
  if (static_cast<int64_t>(mesh.faceSizes.size()) > limits.maxFaces) {
    throwLimit("the mesh has " + std::to_string(mesh.faceSizes.size()) + " faces; the limit is " +
               std::to_string(limits.maxFaces));
  }
  if (mesh.faceSizes.empty()) throwInvalid("the mesh has no faces");
}

void checkFaceSizes(const ControlMesh& mesh, const MeshLimits& limits) {
  int64_t total = 0;
  for (int face = 0; face < mesh.faceCount(); ++face) {
    const int size = mesh.faceSizes[face];
    if (size < 3) {
      throwInvalid("face " + std::to_string(face) + " has " + std::to_string(size) +
                   " vertices; a face needs at least 3");
    }
    if (size > limits.maxFaceSize) {
      throwLimit("face " + std::to_string(face) + " has " + std::to_string(size) +
                 " vertices; the limit is " + std::to_string(limits.maxFaceSize));
    }
    total += size;
  }
  if (total != static_cast<int64_t>(mesh.faceVertices.size())) {
    throwInvalid("the face sizes add up to " + std::to_string(total) + " face vertices, but " +
                 std::to_string(mesh.faceVertices.size()) + " are given");
  }
}

// A face may repeat a vertex, even list one vertex only: OpenSubdiv makes its degenerate edges
// non-manifold and evaluates it (docs/NONMANIFOLD.md), so only the indices are checked.
void checkFaceVertices(const ControlMesh& mesh) {
  size_t corner = 0;
  for (int face = 0; face < mesh.faceCount(); ++face) {
    for (int i = 0; i < mesh.faceSizes[face]; ++i, ++corner) {
      const int vertex = mesh.faceVertices[corner];
      if (vertex < 0 || vertex >= mesh.vertexCount()) {
        throwInvalid("face " + std::to_string(face) + " refers to vertex " +
                     std::to_string(vertex) + ", but the mesh has " +
                     std::to_string(mesh.vertexCount()) + " vertices");
      }
    }
  }
}

// OpenSubdiv refuses a vertex with more faces than its limit only when the topology is built,
// so the cause is named at upload instead.
void checkValences(const ControlMesh& mesh, const MeshLimits& limits) {
  std::vector<int> faces(mesh.positions.size(), 0);
  for (int vertex : mesh.faceVertices) {
    if (++faces[vertex] > limits.maxValence) {
      throwInvalid("vertex " + std::to_string(vertex) + " is shared by more than " +
                   std::to_string(limits.maxValence) + " faces, the most a vertex may have");
    }
  }
}

void checkPositions(const ControlMesh& mesh, const MeshLimits& limits) {
  for (int vertex = 0; vertex < mesh.vertexCount(); ++vertex) {
    const Vec3& p = mesh.positions[vertex];
    for (float c : {p.x, p.y, p.z}) {
      if (!std::isfinite(c)) {
        throwInvalid("vertex " + std::to_string(vertex) + " has a coordinate that is not finite (" +
                     formatNumber(c) + ")");
      }
      if (std::abs(c) > limits.maxAbsCoordinate) {
        throwLimit("vertex " + std::to_string(vertex) + " has coordinate " + formatNumber(c) +
                   ", beyond the limit of " + formatNumber(limits.maxAbsCoordinate) +
                   " in absolute value");
      }
    }
  }
}

// A tolerance is a distance, given or scaled from the bounding-box diagonal (relative, pixels),
// so a mesh whose box is a point has no scale: no tolerance means anything on it, and its limit
// surface is that point. Refused here, so that the server refuses it at upload (not at its first
// Tessellate) and the CLI names the same problem.
void checkBoundingBox(const ControlMesh& mesh) {
  const Vec3& first = mesh.positions[0];
  for (const Vec3& p : mesh.positions) {
    if (p.x != first.x || p.y != first.y || p.z != first.z) return;
  }
  const Vec3d at = Vec3d(first) + mesh.origin;  // as the user wrote it (the OBJ reader may move it)
  // Appended, not `"..." + std::string`: that trips GCC 12's -Wrestrict (105651).
  std::string message = mesh.vertexCount() == 1 ? std::string("the mesh's one vertex is at (")
                                                : "all " + std::to_string(mesh.vertexCount()) + " vertices coincide at (";
  message += formatNumber(at.x);
  message += ", ";
  message += formatNumber(at.y);
  message += ", ";
  message += formatNumber(at.z);
  message += "): the mesh has an empty bounding box (its limit surface is that point), so no tolerance has a scale";
  throwInvalid(message);
}

// Tags are named by kind and index ("crease 3"); the name is built only when there is an error.
std::string tagName(const char* kind, size_t index) {
  std::string name = kind;  // appended: `kind + std::string` trips GCC 12's -Wrestrict (105651)
  name += ' ';
  name += std::to_string(index);
  return name;
}

void checkSharpness(float sharpness, const char* kind, size_t index) {
  if (!std::isfinite(sharpness) || sharpness < 0.0f) {
    throwInvalid(tagName(kind, index) + " has sharpness " + formatNumber(sharpness) +
                 "; sharpness must be a finite number >= 0");
  }
}

void checkVertexReference(int vertex, int vertexCount, const char* kind, size_t index) {
  if (vertex < 0 || vertex >= vertexCount) {
    throwInvalid(tagName(kind, index) + " refers to vertex " + std::to_string(vertex) +
                 ", but the mesh has " + std::to_string(vertexCount) + " vertices");
  }
}

uint64_t undirectedEdgeKey(int a, int b) {
  const auto low = static_cast<uint32_t>(std::min(a, b));
  const auto high = static_cast<uint32_t>(std::max(a, b));
  return (uint64_t{low} << 32) | high;
}

// The distinct crease edges, sorted, and grouped by their lower vertex so that a face edge only
// searches the few creases of its own lower vertex rather than all of them (armorguy has 7101).
class CreaseEdgeIndex {
 public:
  explicit CreaseEdgeIndex(const ControlMesh& mesh) : groupStart_(mesh.positions.size() + 1, 0) {
    keys_.reserve(mesh.creases.size());
    for (const CreaseEdge& crease : mesh.creases) {
      keys_.push_back(undirectedEdgeKey(crease.v0, crease.v1));
    }
    std::sort(keys_.begin(), keys_.end());
    keys_.erase(std::unique(keys_.begin(), keys_.end()), keys_.end());
    for (uint64_t key : keys_) ++groupStart_[(key >> 32) + 1];
    for (size_t v = 1; v < groupStart_.size(); ++v) groupStart_[v] += groupStart_[v - 1];
    found_.assign(keys_.size(), 0);
  }

  void markEdge(int a, int b) {
    const size_t at = find(a, b);
    if (at != kNotFound) found_[at] = 1;
  }

  bool wasMarked(const CreaseEdge& crease) const { return found_[find(crease.v0, crease.v1)]; }

 private:
  static constexpr size_t kNotFound = SIZE_MAX;

  size_t find(int a, int b) const {
    const uint64_t key = undirectedEdgeKey(a, b);
    const auto first = keys_.begin() + groupStart_[std::min(a, b)];
    const auto last = keys_.begin() + groupStart_[std::min(a, b) + 1];
    const auto at = std::lower_bound(first, last, key);
    return at != last && *at == key ? static_cast<size_t>(at - keys_.begin()) : kNotFound;
  }

  std::vector<uint64_t> keys_;
  std::vector<size_t> groupStart_;  // per vertex, into keys_
  std::vector<uint8_t> found_;
};

// The same edge (or vertex) tagged twice must say the same sharpness: which one was meant is
// not for us to guess.
template <typename Key>
void checkRepeatedTags(std::vector<std::tuple<Key, float, size_t>> tags, const char* kind,
                       const std::function<std::string(const Key&)>& name) {
  std::sort(tags.begin(), tags.end());
  for (size_t i = 1; i < tags.size(); ++i) {
    const auto& [key, sharpness, index] = tags[i];
    const auto& [previousKey, previousSharpness, previousIndex] = tags[i - 1];
    if (key != previousKey || sharpness == previousSharpness) continue;
    const auto [first, second] = std::minmax(index, previousIndex);
    throwInvalid(std::string(kind) + "s " + std::to_string(first) + " and " + std::to_string(second) + " both tag " +
                 name(key) + ", with sharpness " + formatNumber(index == first ? sharpness : previousSharpness) +
                 " and " + formatNumber(index == first ? previousSharpness : sharpness));
  }
}

void checkCreasesAreEdges(const ControlMesh& mesh) {
  CreaseEdgeIndex index(mesh);
  size_t faceStart = 0;
  for (int size : mesh.faceSizes) {
    for (int i = 0; i < size; ++i) {
      const int next = i + 1 == size ? 0 : i + 1;
      index.markEdge(mesh.faceVertices[faceStart + i], mesh.faceVertices[faceStart + next]);
    }
    faceStart += size;
  }
  for (size_t i = 0; i < mesh.creases.size(); ++i) {
    const CreaseEdge& crease = mesh.creases[i];
    if (!index.wasMarked(crease)) {
      throwInvalid("crease " + std::to_string(i) + " (" + std::to_string(crease.v0) + ", " +
                   std::to_string(crease.v1) + ") is not an edge of any face");
    }
  }
}

void checkCreases(const ControlMesh& mesh) {
  for (size_t i = 0; i < mesh.creases.size(); ++i) {
    const CreaseEdge& crease = mesh.creases[i];
    checkVertexReference(crease.v0, mesh.vertexCount(), "crease", i);
    checkVertexReference(crease.v1, mesh.vertexCount(), "crease", i);
    if (crease.v0 == crease.v1) {
      throwInvalid(tagName("crease", i) + " joins vertex " + std::to_string(crease.v0) +
                   " to itself");
    }
    checkSharpness(crease.sharpness, "crease", i);
  }
  if (mesh.creases.empty()) return;
  checkCreasesAreEdges(mesh);
  std::vector<std::tuple<uint64_t, float, size_t>> tags;
  for (size_t i = 0; i < mesh.creases.size(); ++i) {
    tags.emplace_back(undirectedEdgeKey(mesh.creases[i].v0, mesh.creases[i].v1), mesh.creases[i].sharpness, i);
  }
  checkRepeatedTags<uint64_t>(std::move(tags), "crease", [](const uint64_t& key) {
    return "edge (" + std::to_string(key >> 32) + ", " + std::to_string(key & UINT32_MAX) + ")";
  });
}

void checkCorners(const ControlMesh& mesh) {
  for (size_t i = 0; i < mesh.corners.size(); ++i) {
    checkVertexReference(mesh.corners[i].vertex, mesh.vertexCount(), "corner", i);
    checkSharpness(mesh.corners[i].sharpness, "corner", i);
  }
  std::vector<std::tuple<int, float, size_t>> tags;
  for (size_t i = 0; i < mesh.corners.size(); ++i) tags.emplace_back(mesh.corners[i].vertex, mesh.corners[i].sharpness, i);
  checkRepeatedTags<int>(std::move(tags), "corner", [](const int& vertex) { return "vertex " + std::to_string(vertex); });
}

void checkHoles(const ControlMesh& mesh) {
  std::vector<uint8_t> isHole(mesh.faceSizes.size(), 0);
  for (size_t i = 0; i < mesh.holes.size(); ++i) {
    const int face = mesh.holes[i];
    if (face < 0 || face >= mesh.faceCount()) {
      throwInvalid("hole " + std::to_string(i) + " refers to face " + std::to_string(face) +
                   ", but the mesh has " + std::to_string(mesh.faceCount()) + " faces");
    }
    if (isHole[face]) {
      throwInvalid("hole " + std::to_string(i) + " lists face " + std::to_string(face) +
                   ", which is already a hole");
    }
    isHole[face] = 1;
  }
}

// Texture coordinates: one index per face corner when there are any, each naming a finite pair.
void checkUvs(const ControlMesh& mesh) {
  if (mesh.uvs.size() % 2 != 0) throwInvalid("the UVs hold " + std::to_string(mesh.uvs.size()) + " numbers; u and v come in pairs");
  if (mesh.uvIndices.empty()) {
    if (!mesh.uvs.empty()) throwInvalid("the mesh has UVs but no face corner uses one (UV indices missing)");
    return;
  }
  if (mesh.uvIndices.size() != mesh.faceVertices.size()) {
    throwInvalid("the mesh has " + std::to_string(mesh.uvIndices.size()) + " UV indices for " +
                 std::to_string(mesh.faceVertices.size()) + " face corners; every corner needs one");
  }
  for (size_t i = 0; i < mesh.uvs.size(); ++i) {
    if (!std::isfinite(mesh.uvs[i])) {
      throwInvalid("UV " + std::to_string(i / 2) + " has a coordinate that is not finite (" + formatNumber(mesh.uvs[i]) + ")");
    }
  }
  const int64_t count = int64_t(mesh.uvs.size() / 2);
  size_t corner = 0;
  for (int face = 0; face < mesh.faceCount(); ++face) {
    for (int k = 0; k < mesh.faceSizes[face]; ++k, ++corner) {
      const int uv = mesh.uvIndices[corner];
      if (uv < 0 || uv >= count) {
        throwInvalid("face " + std::to_string(face) + " corner " + std::to_string(k) + " uses UV " + std::to_string(uv) +
                     ", but the mesh has " + std::to_string(count) + " UVs");
      }
    }
  }
}

}  // namespace

void validateControlMesh(const ControlMesh& mesh, const MeshLimits& limits) {
  checkCounts(mesh, limits);
  checkFaceSizes(mesh, limits);
  checkFaceVertices(mesh);
  checkValences(mesh, limits);
  checkPositions(mesh, limits);
  checkBoundingBox(mesh);
  checkCreases(mesh);
  checkCorners(mesh);
  checkHoles(mesh);
  checkUvs(mesh);
}

}  // namespace tessera
