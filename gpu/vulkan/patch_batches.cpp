#include "gpu/vulkan/patch_batches.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "gpu/vulkan/vulkan_error.h"
#include "shaders/include/tess_pattern_counts.h"

namespace tessera::gpu {
namespace {

// Edge level k as the pattern uses it: at least 1 (and at most 64, which validatePatches checks).
int levelOf(const uint32_t edgeLevels[4], int k) {
  return int(std::max(edgeLevels[k], 1u));
}

void fail(size_t index, const std::string& what) {
  throw RenderInputError("patch " + std::to_string(index) + ": " + what);
}

}  // namespace

uint32_t patternVertexCount(const uint32_t edgeLevels[4]) {
  auto e = [&](int k) { return levelOf(edgeLevels, k); };
  return uint32_t(tessPatternVertices(e(0), e(1), e(2), e(3)));
}

uint32_t patternTriangleCount(const uint32_t edgeLevels[4]) {
  auto e = [&](int k) { return levelOf(edgeLevels, k); };
  return uint32_t(tessPatternTriangles(e(0), e(1), e(2), e(3)));
}

void validatePatches(std::span<const RenderPatch> patches, uint32_t uniformLevel) {
  if (uniformLevel > kMaxTessellationLevel) {
    throw RenderInputError("uniform tessellation level " + std::to_string(uniformLevel) +
                           " exceeds the maximum of " + std::to_string(kMaxTessellationLevel));
  }
  for (size_t i = 0; i < patches.size(); ++i) {
    const RenderPatch& p = patches[i];
    for (const auto& c : p.controlPoints) {
      if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2])) {
        fail(i, "control points must be finite");
      }
    }
    if (p.patchId == kBackgroundPatchId) fail(i, "patch id 0xFFFFFFFF is reserved for background");
    if (uniformLevel != 0) continue;
    for (int k = 0; k < 4; ++k) {
      if (p.edgeLevels[k] < 1 || p.edgeLevels[k] > kMaxTessellationLevel) {
        fail(i, "edge level " + std::to_string(k) + " is " + std::to_string(p.edgeLevels[k]) +
                    "; it must be between 1 and " + std::to_string(kMaxTessellationLevel));
      }
    }
  }
}

PatchUpload planBatches(std::span<const RenderPatch> patches, uint32_t uniformLevel,
                        const BatchLimits& limits) {
  PatchUpload upload;
  upload.patches.resize(patches.size());
  GeometryBatch batch;
  auto closeBatch = [&] {
    if (batch.patchCount == 0) return;
    upload.largestBatchVertices = std::max(upload.largestBatchVertices, batch.vertexCount);
    upload.largestBatchTriangles = std::max(upload.largestBatchTriangles, batch.triangleCount);
    upload.batches.push_back(batch);
    batch = GeometryBatch{batch.firstPatch + batch.patchCount, 0, 0, 0};
  };
  for (size_t i = 0; i < patches.size(); ++i) {
    const RenderPatch& p = patches[i];
    GpuPatch& g = upload.patches[i];
    std::copy(&p.controlPoints[0][0], &p.controlPoints[0][0] + 48, g.controlPoints);
    for (int k = 0; k < 4; ++k) g.levels[k] = uniformLevel ? uniformLevel : p.edgeLevels[k];
    g.patchId = p.patchId;
    uint64_t vertices = patternVertexCount(g.levels);
    uint64_t triangles = patternTriangleCount(g.levels);
    bool full = batch.patchCount == limits.maxPatches ||
                batch.vertexCount + vertices > limits.maxVertices ||
                batch.triangleCount + triangles > limits.maxTriangles;
    if (full) closeBatch();
    g.firstVertex = static_cast<uint32_t>(batch.vertexCount);
    g.firstTriangle = static_cast<uint32_t>(batch.triangleCount);
    g.unused = 0;
    batch.patchCount += 1;
    batch.vertexCount += vertices;
    batch.triangleCount += triangles;
  }
  closeBatch();
  return upload;
}

}  // namespace tessera::gpu
