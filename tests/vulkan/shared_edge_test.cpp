// Watertightness across a shared edge: two patches that agree on the edge's level and share
// its control points must leave no pixel of the square they cover unpainted, even though the
// edge runs in opposite directions on the two sides and their interior levels differ.
#include <gtest/gtest.h>

#include "render_test_support.h"
#include "two_patch_scenes.h"

namespace tessera::gpu::testing {
namespace {

// 2 px at the 88 px-per-unit scale of topDownCamera keeps pixels on the square's outer
// border (partly covered by design) out of the count; the seam runs through the middle.
constexpr double kInset = 0.025;

TEST(SharedEdge, EqualLevelsLeaveNoDropout) {
  Renderer renderer = makeTestRenderer();
  Camera camera = topDownCamera();
  RenderOptions options;
  options.crackFilling = false;
  for (uint32_t level : {1u, 2u, 5u, 13u, 64u}) {
    SCOPED_TRACE("shared edge level " + std::to_string(level));
    // A strong bulge: with mismatched levels this seam would open by several pixels.
    std::vector<RenderPatch> patches = twoPatchesWithCurvedSeam(0.4, level, level);
    Frame frame = renderer.render(patches, camera, options);
    EXPECT_EQ(pixelsNotShowingPair(frame, camera, kInset), 0u);
    EXPECT_EQ(countDropouts(frame), 0u);
  }
  expectNoValidationMessages(renderer);
}

TEST(SharedEdge, CrackFillingChangesNothingOnAWatertightImage) {
  // No false positives: on a crack-free image neither the isolation nor the occlusion
  // criterion may fire (the paper's reason for adding the occlusion test).
  Renderer renderer = makeTestRenderer();
  Camera camera = topDownCamera();
  std::vector<RenderPatch> patches = twoPatchesWithCurvedSeam(0.4, 5, 5);
  patches.push_back(backPlane());
  RenderOptions off;
  off.crackFilling = false;
  RenderOptions on;
  on.crackFilling = true;
  Frame plain = renderer.render(patches, camera, off);
  Frame filled = renderer.render(patches, camera, on);
  EXPECT_EQ(plain.patchIds, filled.patchIds);
  EXPECT_EQ(plain.rgba, filled.rgba);
  EXPECT_EQ(plain.depth, filled.depth);
  expectNoValidationMessages(renderer);
}

}  // namespace
}  // namespace tessera::gpu::testing
