// Crack filling (paper §6.2.4). A deliberately mismatched edge level (2 on one side, 7 on the
// other) opens a sliver crack along a curved seam; the bulge is chosen so the sliver is under
// a pixel wide (~0.19·bulge world units between the level-2 chord and the curve, at 88 px per
// unit), which is the crack size pixel-accurate tessellation produces and the filler handles.
#include <gtest/gtest.h>

#include "render_test_support.h"
#include "two_patch_scenes.h"

namespace tessera::gpu::testing {
namespace {

constexpr double kBulge = 0.05;
constexpr double kInset = 0.025;

RenderOptions withCrackFilling(bool on) {
  RenderOptions options;
  options.crackFilling = on;
  options.background = {0.2f, 0.3f, 0.4f, 1.0f};
  return options;
}

TEST(CrackFilling, RepairsDropoutsFromMismatchedEdgeLevels) {
  Renderer renderer = makeTestRenderer();
  Camera camera = topDownCamera();
  std::vector<RenderPatch> patches = twoPatchesWithCurvedSeam(kBulge, 2, 7);
  Frame before = renderer.render(patches, camera, withCrackFilling(false));
  Frame after = renderer.render(patches, camera, withCrackFilling(true));
  dumpFrame(before, "crack_dropout_before");
  dumpFrame(after, "crack_dropout_after");
  size_t holesBefore = pixelsNotShowingPair(before, camera, kInset);
  RecordProperty("holes_before", std::to_string(holesBefore));
  // The crack must really be there, or this test proves nothing.
  EXPECT_GE(holesBefore, 10u);
  EXPECT_EQ(countDropouts(before), holesBefore);
  EXPECT_EQ(pixelsNotShowingPair(after, camera, kInset), 0u);
  EXPECT_EQ(countDropouts(after), 0u);
  // Filled pixels take a neighbour's colour: none keeps the background colour.
  for (size_t i = 0; i < after.patchIds.size(); ++i) {
    if (after.patchIds[i] != kBackgroundPatchId) {
      ASSERT_NE(after.rgba[4 * i + 2], uint8_t(0.4f * 255 + 0.5f)) << "pixel " << i;
    }
  }
  expectNoValidationMessages(renderer);
}

TEST(CrackFilling, RepairsCracksShowingHiddenGeometry) {
  // The same crack in front of a plane: the crack now shows the plane (covered, but by a
  // triangle entirely behind its neighbours' triangles) — the paper's case 2.
  Renderer renderer = makeTestRenderer();
  Camera camera = topDownCamera();
  std::vector<RenderPatch> patches = twoPatchesWithCurvedSeam(kBulge, 2, 7);
  patches.push_back(backPlane());
  Frame before = renderer.render(patches, camera, withCrackFilling(false));
  Frame after = renderer.render(patches, camera, withCrackFilling(true));
  dumpFrame(before, "crack_occluded_before");
  size_t showingBack = pixelsNotShowingPair(before, camera, kInset);
  RecordProperty("back_pixels_before", std::to_string(showingBack));
  EXPECT_GE(showingBack, 10u);
  EXPECT_EQ(countDropouts(before), 0u);  // nothing is background inside the pair
  EXPECT_EQ(pixelsNotShowingPair(after, camera, kInset), 0u);
  // Outside the pair the plane is legitimately visible and must stay untouched.
  size_t backOutside = 0;
  for (uint32_t id : after.patchIds) backOutside += id == kBackId;
  EXPECT_GT(backOutside, 1000u);
  expectNoValidationMessages(renderer);
}

TEST(CrackFilling, CanBeTurnedOff) {
  Renderer renderer = makeTestRenderer();
  std::vector<RenderPatch> patches = twoPatchesWithCurvedSeam(kBulge, 2, 7);
  Frame frame = renderer.render(patches, topDownCamera(), withCrackFilling(false));
  EXPECT_EQ(frame.timings.crackFillingMs, 0.0);
  EXPECT_GT(countDropouts(frame), 0u);
}

}  // namespace
}  // namespace tessera::gpu::testing
