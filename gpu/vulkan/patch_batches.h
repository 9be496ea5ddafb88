// From the caller's RenderPatch array to what the GPU reads: validation, the packed GpuPatch
// records (shaders/include/patch_data.glsl), and a split into batches whose tessellated
// vertices and triangles fit the geometry buffers. Plain CPU code, testable without a device.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "gpu/vulkan/render_types.h"

namespace tessera::gpu {

struct GpuPatch {
  float controlPoints[48];
  uint32_t levels[4];
  uint32_t patchId;
  uint32_t firstVertex;    // batch-relative
  uint32_t firstTriangle;  // batch-relative
  uint32_t unused;
};
static_assert(sizeof(GpuPatch) == 224, "must match GpuPatch in shaders/include/patch_data.glsl");

// Counts of the tessellation pattern, by the formulas the shaders use
// (shaders/include/tess_pattern_counts.h).
uint32_t patternVertexCount(const uint32_t edgeLevels[4]);
uint32_t patternTriangleCount(const uint32_t edgeLevels[4]);

struct GeometryBatch {
  uint32_t firstPatch = 0;
  uint32_t patchCount = 0;
  uint64_t vertexCount = 0;
  uint64_t triangleCount = 0;
};

struct BatchLimits {
  uint64_t maxVertices = ~0ull;
  uint64_t maxTriangles = ~0ull;
  uint32_t maxPatches = 1u << 20;
};

struct PatchUpload {
  std::vector<GpuPatch> patches;
  std::vector<GeometryBatch> batches;
  uint64_t largestBatchVertices = 0;
  uint64_t largestBatchTriangles = 0;
};

// Throws RenderInputError naming the first bad patch: non-finite control points, an edge level
// outside [1, kMaxTessellationLevel], or the reserved id kBackgroundPatchId. A uniformLevel
// above kMaxTessellationLevel is refused the same way.
void validatePatches(std::span<const RenderPatch> patches, uint32_t uniformLevel);

// Packs the patches (uniformLevel ≥ 1 replaces every edge level) and cuts them, in order, into
// batches within `limits`. A single patch always fits (a level-64 patch is 8192 triangles).
PatchUpload planBatches(std::span<const RenderPatch> patches, uint32_t uniformLevel,
                        const BatchLimits& limits);

}  // namespace tessera::gpu
