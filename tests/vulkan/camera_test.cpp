// Bad cameras and bad patches are refused with a message naming the problem; a valid camera
// that sees nothing yields a background frame (the patches are culled, not drawn off-screen).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gpu/vulkan/vulkan_error.h"
#include "render_test_support.h"
#include "two_patch_scenes.h"

namespace tessera::gpu::testing {
namespace {

// Runs render() and returns the RenderInputError message ("" if nothing was thrown).
std::string renderError(Renderer& renderer, const std::vector<RenderPatch>& patches,
                        const Camera& camera, const RenderOptions& options = {}) {
  try {
    renderer.render(patches, camera, options);
  } catch (const RenderInputError& e) {
    return e.what();
  }
  return "";
}

TEST(CameraValidation, BadCamerasAreClearErrors) {
  Renderer renderer = makeTestRenderer();
  std::vector<RenderPatch> patches = twoPatchesWithCurvedSeam(0.2, 3, 3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  struct Case {
    const char* name;
    Camera camera;
    const char* mentions;
  };
  Camera base = topDownCamera(64);
  std::vector<Case> cases;
  auto add = [&](const char* name, auto change, const char* mentions) {
    Camera c = base;
    change(c);
    cases.push_back({name, c, mentions});
  };
  add(
      "NaN eye", [&](Camera& c) { c.eye.x = nan; }, "finite");
  add(
      "infinite target", [&](Camera& c) { c.target.y = INFINITY; }, "finite");
  add(
      "eye == target", [&](Camera& c) { c.target = c.eye; }, "same point");
  add(
      "zero up", [&](Camera& c) { c.up = Vec3(0, 0, 0); }, "up");
  add(
      "up along view", [&](Camera& c) { c.up = Vec3(0, 0, 1); }, "parallel");
  add(
      "zero width", [&](Camera& c) { c.width = 0; }, "width");
  add(
      "zero height", [&](Camera& c) { c.height = 0; }, "height");
  add(
      "width 8193", [&](Camera& c) { c.width = 8193; }, "8192");
  add(
      "height 100000", [&](Camera& c) { c.height = 100000; }, "8192");
  add(
      "fov 0", [&](Camera& c) { c.fovYDegrees = 0.0f; }, "fovYDegrees");
  add(
      "fov 180", [&](Camera& c) { c.fovYDegrees = 180.0f; }, "fovYDegrees");
  add(
      "fov NaN", [&](Camera& c) { c.fovYDegrees = nan; }, "fovYDegrees");
  add(
      "far < near", [&](Camera& c) { c.nearPlane = 2.0f, c.farPlane = 1.0f; }, "near");
  for (const Case& c : cases) {
    std::string message = renderError(renderer, patches, c.camera);
    EXPECT_NE(message.find(c.mentions), std::string::npos)
        << c.name << ": got \"" << message << "\"";
  }
  // The renderer stays usable after refusing input.
  Frame frame = renderer.render(patches, base, RenderOptions{});
  EXPECT_EQ(frame.width, 64u);
  expectNoValidationMessages(renderer);
}

TEST(CameraValidation, BadPatchesAndOptionsAreClearErrors) {
  Renderer renderer = makeTestRenderer();
  Camera camera = topDownCamera(32);
  std::vector<RenderPatch> good = twoPatchesWithCurvedSeam(0.2, 3, 3);
  auto withPatch = [&](auto change) {
    std::vector<RenderPatch> p = good;
    change(p[1]);
    return p;
  };
  EXPECT_NE(renderError(renderer, withPatch([](RenderPatch& p) { p.edgeLevels[2] = 0; }), camera)
                .find("patch 1: edge level 2 is 0"),
            std::string::npos);
  EXPECT_NE(renderError(renderer, withPatch([](RenderPatch& p) { p.edgeLevels[0] = 65; }), camera)
                .find("edge level 0 is 65"),
            std::string::npos);
  EXPECT_NE(
      renderError(renderer, withPatch([](RenderPatch& p) { p.controlPoints[5][1] = NAN; }), camera)
          .find("finite"),
      std::string::npos);
  EXPECT_NE(renderError(renderer, withPatch([](RenderPatch& p) { p.patchId = kBackgroundPatchId; }),
                        camera)
                .find("reserved"),
            std::string::npos);
  RenderOptions tooFine;
  tooFine.uniformLevel = 65;
  EXPECT_NE(renderError(renderer, good, camera, tooFine).find("uniform"), std::string::npos);
  RenderOptions badBackground;
  badBackground.background = {0.0f, 2.0f, 0.0f, 1.0f};
  EXPECT_NE(renderError(renderer, good, camera, badBackground).find("background"),
            std::string::npos);
}

TEST(CameraValidation, CameraLookingAwayGivesBackgroundFrame) {
  Renderer renderer = makeTestRenderer();
  std::vector<RenderPatch> patches = makeSphere(Vec3d(0, 0, 0), 1.0, 2, hashedEdgeLevels(3, 8), 1);
  Camera camera = topDownCamera(64);
  camera.eye = Vec3(0.0f, 0.0f, 4.0f);
  camera.target = Vec3(0.0f, 0.0f, 8.0f);  // facing +z, the sphere is behind
  RenderOptions options;
  options.background = {0.25f, 0.5f, 0.75f, 1.0f};
  Frame frame = renderer.render(patches, camera, options);
  EXPECT_EQ(frame.patchesCulled, patches.size());
  EXPECT_EQ(frame.trianglesGenerated, 0u);
  for (size_t i = 0; i < frame.patchIds.size(); ++i) {
    ASSERT_EQ(frame.patchIds[i], kBackgroundPatchId);
    ASSERT_EQ(frame.depth[i], 1.0f);
    // Vulkan's float → UNORM conversion may give either integer next to f · 255 (lavapipe
    // rounds 127.5 to 128, NVIDIA to 127): 63.75, 127.5, 191.25, 255.
    for (int channel = 0; channel < 4; ++channel) {
      const float exact = options.background[channel] * 255.0f;
      ASSERT_GE(frame.rgba[4 * i + channel], std::floor(exact)) << "channel " << channel;
      ASSERT_LE(frame.rgba[4 * i + channel], std::ceil(exact)) << "channel " << channel;
    }
  }
  expectNoValidationMessages(renderer);
}

TEST(CameraValidation, EmptyPatchListGivesBackgroundFrame) {
  Renderer renderer = makeTestRenderer();
  Frame frame = renderer.render({}, topDownCamera(16), RenderOptions{});
  EXPECT_EQ(frame.patchIds, std::vector<uint32_t>(16 * 16, kBackgroundPatchId));
}

TEST(CameraValidation, LargestSideIsAccepted) {
  Renderer renderer = makeTestRenderer();
  Camera camera = topDownCamera(8);
  camera.width = kMaxTargetSize;
  camera.fovYDegrees = 2.0f;  // keeps the 1024:1 frame's horizontal view narrow
  Frame frame = renderer.render(twoPatchesWithCurvedSeam(0.2, 3, 3), camera, RenderOptions{});
  EXPECT_EQ(frame.width, kMaxTargetSize);
  EXPECT_EQ(frame.patchIds.size(), size_t(kMaxTargetSize) * 8);
  EXPECT_EQ(frame.patchIdAt(kMaxTargetSize / 2 - 20, 4), kLeftId);
  EXPECT_EQ(frame.patchIdAt(kMaxTargetSize / 2 + 20, 4), kRightId);
  expectNoValidationMessages(renderer);
}

}  // namespace
}  // namespace tessera::gpu::testing
