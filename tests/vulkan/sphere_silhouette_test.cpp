// A closed surface (a sphere of 24 Bézier patches with stitched, per-edge levels) must render
// with the silhouette of an independent CPU rasterisation of the same surface, and without
// holes: watertightness comes from bit-identical shared edges, not from crack filling.
#include <gtest/gtest.h>

#include "render_test_support.h"

namespace tessera::gpu::testing {
namespace {

struct SphereScene {
  std::vector<RenderPatch> patches;
  Camera camera;
};

// Off-centre in the image, so a flipped axis or a wrong aspect would move the silhouette.
SphereScene sphereScene(uint32_t size) {
  SphereScene s;
  s.patches = makeSphere(Vec3d(0.45, -0.3, 0.0), 1.0, 2, hashedEdgeLevels(6, 16), 100);
  s.camera.eye = Vec3(0.6f, 0.9f, 4.2f);
  s.camera.target = Vec3(0.0f, 0.0f, 0.0f);
  s.camera.width = size;
  s.camera.height = size;
  s.camera.fovYDegrees = 50.0f;
  return s;
}

double intersectionOverUnion(const Frame& frame, const std::vector<uint8_t>& reference) {
  size_t both = 0, either = 0;
  for (size_t i = 0; i < reference.size(); ++i) {
    bool gpu = frame.patchIds[i] != kBackgroundPatchId;
    both += gpu && reference[i];
    either += gpu || reference[i];
  }
  return either ? double(both) / double(either) : 1.0;
}

// Background pixels whose whole 5×5 neighbourhood is covered in the reference: inside the
// silhouette by more than the tessellation's chordal error (far below a pixel here).
size_t holesInside(const Frame& frame, const std::vector<uint8_t>& reference) {
  size_t holes = 0;
  int w = int(frame.width), h = int(frame.height);
  for (int y = 2; y < h - 2; ++y) {
    for (int x = 2; x < w - 2; ++x) {
      if (frame.patchIdAt(x, y) != kBackgroundPatchId) continue;
      bool interior = true;
      for (int dy = -2; dy <= 2 && interior; ++dy) {
        for (int dx = -2; dx <= 2 && interior; ++dx) interior = reference[(y + dy) * w + x + dx];
      }
      holes += interior;
    }
  }
  return holes;
}

TEST(SphereSilhouette, MatchesCpuRasterizationAt512) {
  SphereScene scene = sphereScene(512);
  Renderer renderer = makeTestRenderer();
  RenderOptions options;
  options.crackFilling = false;  // judge the geometry itself
  Frame frame = renderer.render(scene.patches, scene.camera, options);
  dumpFrame(frame, "sphere_silhouette");
  std::vector<uint8_t> reference = rasterizeCoverage(scene.patches, scene.camera, 64);

  // Tessellation levels ≥ 6 on a quarter-face patch keep the chordal error below 0.3 px at
  // this size, so only pixels whose centres lie within that of the silhouette may differ:
  // a ~1300 px perimeter bounds the mismatch well under 1% of the ~60k covered pixels.
  double iou = intersectionOverUnion(frame, reference);
  RecordProperty("iou", std::to_string(iou));
  EXPECT_GE(iou, 0.99);
  EXPECT_EQ(holesInside(frame, reference), 0u);
  EXPECT_EQ(countDropouts(frame), 0u);
  EXPECT_EQ(frame.patchesCulled, 0u);
  expectNoValidationMessages(renderer);
}

TEST(SphereSilhouette, UniformLevelIsWatertightToo) {
  SphereScene scene = sphereScene(192);
  Renderer renderer = makeTestRenderer();
  RenderOptions options;
  options.crackFilling = false;
  options.uniformLevel = 5;
  Frame frame = renderer.render(scene.patches, scene.camera, options);
  std::vector<uint8_t> reference = rasterizeCoverage(scene.patches, scene.camera, 32);
  EXPECT_EQ(holesInside(frame, reference), 0u);
  EXPECT_EQ(countDropouts(frame), 0u);
  EXPECT_EQ(frame.trianglesGenerated, scene.patches.size() * 2u * 5u * 5u);
  expectNoValidationMessages(renderer);
}

}  // namespace
}  // namespace tessera::gpu::testing
