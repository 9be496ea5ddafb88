// The patch-ID target names, for every pixel, the patch whose surface covers it: a 3×3 grid of
// planar patches seen obliquely, with the outer patches cut by the image border (so frustum
// culling must keep partly visible patches), checked pixel by pixel against ray casting.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "render_test_support.h"

namespace tessera::gpu::testing {
namespace {

constexpr uint32_t kFirstId = 1000;

std::vector<RenderPatch> patchGrid() {
  std::vector<RenderPatch> patches;
  for (int b = 0; b < 3; ++b) {
    for (int a = 0; a < 3; ++a) {
      ControlNet net = planarNet(Vec3d(-1.5 + a, -1.5 + b, 0.0), Vec3d(1, 0, 0), Vec3d(0, 1, 0));
      patches.push_back(makePatch(net, {3, 4, 5, 6}, kFirstId + 3 * b + a));
    }
  }
  return patches;
}

TEST(PatchIds, EveryPixelShowsThePatchItsRayHits) {
  Renderer renderer = makeTestRenderer();
  std::vector<RenderPatch> patches = patchGrid();
  Camera camera;
  camera.eye = Vec3(0.6f, -1.2f, 2.6f);
  camera.target = Vec3(0.1f, 0.2f, 0.0f);
  camera.width = 160;
  camera.height = 120;
  camera.fovYDegrees = 60.0f;
  Frame frame = renderer.render(patches, camera, RenderOptions{});
  dumpFrame(frame, "patch_ids");

  Pinhole pinhole(camera);
  size_t checked = 0, wrong = 0;
  std::set<uint32_t> seen;
  for (uint32_t y = 0; y < frame.height; ++y) {
    for (uint32_t x = 0; x < frame.width; ++x) {
      seen.insert(frame.patchIdAt(x, y));
      Vec3d hit;
      if (!pinhole.hitPlaneZ(x, y, 0.0, hit)) continue;
      double gx = hit.x + 1.5, gy = hit.y + 1.5;  // grid coordinates, cells of size 1
      // Skip pixels whose ray lands within 0.02 of a cell border (about a pixel here).
      double fx = gx - std::floor(gx), fy = gy - std::floor(gy);
      bool nearBorder = fx < 0.02 || fx > 0.98 || fy < 0.02 || fy > 0.98;
      if (nearBorder) continue;
      bool inside = gx > 0 && gx < 3 && gy > 0 && gy < 3;
      uint32_t expected = inside ? kFirstId + 3 * uint32_t(gy) + uint32_t(gx) : kBackgroundPatchId;
      ++checked;
      wrong += frame.patchIdAt(x, y) != expected;
    }
  }
  EXPECT_GT(checked, frame.width * frame.height / 2);
  EXPECT_EQ(wrong, 0u);
  std::set<uint32_t> drawn = {kBackgroundPatchId};
  for (const RenderPatch& p : patches) drawn.insert(p.patchId);
  EXPECT_EQ(seen, drawn);
  expectNoValidationMessages(renderer);
}

}  // namespace
}  // namespace tessera::gpu::testing
