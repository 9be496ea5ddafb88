#include "core/pipeline/memory_estimates.h"

#include <vector>

namespace tessera {

namespace {

// Peaks measured on ../shared/models (bench/MEMORY-RESULTS.md), rounded up.
constexpr int64_t kRefinementBytesPerVertex = 512;      // 305-437 measured
constexpr int64_t kPreprocessingBytesPerVertex = 700;   // 445-595 after the irregular part
constexpr int64_t kBytesPerIrregularIncidence = 24 << 10;
constexpr int64_t kBytesPerSquaredValence = 4;          // rings of very high valence
constexpr int64_t kPreprocessingBytesPerFace = 2 << 10;
constexpr int64_t kTessellationBytesPerTriangle = 448;  // up to 410 measured (uniform level 3)
constexpr int64_t kTessellationBaseBytes = 16 << 20;
// Not measured: the arrays UVs add, counted from their types with every vertex a seam copy
// (triangle parameters 60, per-corner keys and queries 3 × 48, copies' position, normal, UV 32).
constexpr int64_t kUvBytesPerTriangle = 256;

}  // namespace

int64_t refinementBytes(int64_t refinedVertices) { return kRefinementBytesPerVertex * refinedVertices; }

int64_t preprocessingBytes(const ControlMesh& mesh, int64_t refinedVertices) {
  // Faces around each vertex stand for its valence (one less than it on a boundary).
  std::vector<int64_t> faces(mesh.positions.size(), 0);
  for (int v : mesh.faceVertices) ++faces[size_t(v)];
  int64_t incidences = 0, squared = 0;
  for (int64_t n : faces) {
    if (n == 4 || n == 0) continue;
    incidences += n + 1;
    squared += (n + 1) * (n + 1);
  }
  for (int size : mesh.faceSizes) {
    if (size != 4) incidences += size, squared += int64_t(size) * size;
  }
  return kPreprocessingBytesPerVertex * refinedVertices + kBytesPerIrregularIncidence * incidences +
         kBytesPerSquaredValence * squared + kPreprocessingBytesPerFace * mesh.faceCount();
}

int64_t tessellationBytes(int64_t triangles, bool uvs) {
  return kTessellationBaseBytes + (kTessellationBytesPerTriangle + (uvs ? kUvBytesPerTriangle : 0)) * triangles;
}

}  // namespace tessera
