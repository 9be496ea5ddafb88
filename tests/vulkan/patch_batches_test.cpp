// The tessellation pattern's counts and the batch split, checked against closed forms and
// against what the GPU actually generated.
#include "gpu/vulkan/patch_batches.h"

#include <gtest/gtest.h>

#include <numeric>

#include "render_test_support.h"
#include "two_patch_scenes.h"

namespace tessera::gpu::testing {
namespace {

TEST(PatchBatches, UniformLevelCountsAreTheRegularGrid) {
  for (uint32_t p = 1; p <= kMaxTessellationLevel; ++p) {
    uint32_t levels[4] = {p, p, p, p};
    EXPECT_EQ(patternVertexCount(levels), (p + 1) * (p + 1)) << p;
    EXPECT_EQ(patternTriangleCount(levels), 2 * p * p) << p;
  }
}

TEST(PatchBatches, MixedLevelCountsMatchEulersFormula) {
  // A triangulated disc has V − E + F = 1 and 3F = 2E − B (B boundary edges), so
  // F = 2V − B − 2: an independent check of the stitched pattern's counts.
  for (uint32_t a = 1; a <= 9; ++a) {
    for (uint32_t b = 1; b <= 9; b += 2) {
      for (uint32_t c : {1u, 4u, 16u}) {
        uint32_t levels[4] = {a, b, c, 3};
        uint32_t boundary = a + b + c + 3;
        EXPECT_EQ(patternTriangleCount(levels), 2 * patternVertexCount(levels) - boundary - 2)
            << a << " " << b << " " << c;
      }
    }
  }
}

TEST(PatchBatches, SplitsInOrderWithinLimits) {
  std::vector<RenderPatch> patches = makeSphere(Vec3d(0, 0, 0), 1.0, 3, hashedEdgeLevels(1, 20), 0);
  BatchLimits limits;
  limits.maxTriangles = 3000;
  PatchUpload upload = planBatches(patches, 0, limits);
  ASSERT_GT(upload.batches.size(), 1u);
  uint32_t next = 0;
  for (const GeometryBatch& batch : upload.batches) {
    EXPECT_EQ(batch.firstPatch, next);
    EXPECT_LE(batch.triangleCount, limits.maxTriangles);
    uint64_t triangles = 0, vertices = 0;
    for (uint32_t i = batch.firstPatch; i < batch.firstPatch + batch.patchCount; ++i) {
      EXPECT_EQ(upload.patches[i].firstTriangle, triangles);
      EXPECT_EQ(upload.patches[i].firstVertex, vertices);
      triangles += patternTriangleCount(upload.patches[i].levels);
      vertices += patternVertexCount(upload.patches[i].levels);
    }
    EXPECT_EQ(batch.triangleCount, triangles);
    EXPECT_EQ(batch.vertexCount, vertices);
    next += batch.patchCount;
  }
  EXPECT_EQ(next, patches.size());
}

TEST(PatchBatches, GpuGeneratesTheCountedTriangles) {
  Renderer renderer = makeTestRenderer();
  std::vector<RenderPatch> patches = makeSphere(Vec3d(0, 0, 0), 1.0, 2, hashedEdgeLevels(1, 30), 0);
  patches[3].edgeLevels[0] = patches[3].edgeLevels[1] = 1;  // thin-patch zipper cases
  patches[3].edgeLevels[2] = 1;
  patches[5].edgeLevels[1] = patches[5].edgeLevels[3] = 1;
  Camera camera;
  camera.width = camera.height = 64;
  Frame frame = renderer.render(patches, camera, RenderOptions{});
  uint64_t expected = 0;
  for (const RenderPatch& p : patches) expected += patternTriangleCount(p.edgeLevels);
  EXPECT_EQ(frame.trianglesGenerated, expected);
  EXPECT_EQ(frame.patchesCulled, 0u);
}

TEST(PatchBatches, ManySmallBatchesDrawTheSameImage) {
  Renderer renderer = makeTestRenderer();
  std::vector<RenderPatch> patches = makeSphere(Vec3d(0, 0, 0), 1.0, 2, hashedEdgeLevels(4, 12), 0);
  Camera camera;
  camera.width = camera.height = 96;
  RenderOptions one;
  RenderOptions many;
  many.maxBatchTriangles = 400;
  Frame a = renderer.render(patches, camera, one);
  Frame b = renderer.render(patches, camera, many);
  EXPECT_EQ(a.batches, 1u);
  EXPECT_GT(b.batches, 5u);
  EXPECT_EQ(a.patchIds, b.patchIds);
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_EQ(a.trianglesGenerated, b.trianglesGenerated);
  expectNoValidationMessages(renderer);
}

}  // namespace
}  // namespace tessera::gpu::testing
