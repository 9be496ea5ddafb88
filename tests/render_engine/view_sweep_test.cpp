// The Table 3 helper: cameras that frame the model from every side, and sane statistics.
#include "gpu/render_engine/view_sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/base/error.h"
#include "tests/render_engine/engine_test_support.h"

namespace tessera::testing {
namespace {

TEST(ViewSweep, CamerasKeepTheWholeModelInViewFromEverySide) {
  const LoadedModel& model = loadModel("bigguy");
  gpu::ViewSweep sweep;
  sweep.anglesPerAxis = 4;
  std::vector<tessera::Camera> cameras = gpu::sweepCameras(model.patches, sweep);
  ASSERT_EQ(cameras.size(), 16u);
  Vec3d lo(model.patches.boundsMin), hi(model.patches.boundsMax);
  for (const tessera::Camera& c : cameras) {
    EXPECT_NEAR(length(c.target - model.centre), 0, 1e-9);
    EXPECT_NEAR(dot(c.up, c.target - c.eye), 0, 1e-9 * length(c.target - c.eye));
    // Every corner of the bounding box is in front of the eye and projects into the viewport,
    // and one of them comes within 3% of its border: the model fills the view.
    Vec3d f = (c.target - c.eye) * (1 / length(c.target - c.eye));
    Vec3d s = cross(f, c.up) * (1 / length(cross(f, c.up)));
    Vec3d u = cross(s, f);
    double tanY = std::tan(c.fovYDegrees * M_PI / 360), tanX = tanY * c.width / c.height;
    double widest = 0;
    for (int k = 0; k < 8; ++k) {
      Vec3d p(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
      Vec3d d = p - c.eye;
      double z = dot(d, f);
      ASSERT_GT(z, 0);
      widest =
          std::max({widest, std::abs(dot(d, s)) / (z * tanX), std::abs(dot(d, u)) / (z * tanY)});
    }
    EXPECT_LE(widest, 1.0);
    EXPECT_GE(widest, 0.97);
  }
  // Distinct views: no two cameras at the same place with the same up.
  for (size_t a = 0; a < cameras.size(); ++a) {
    for (size_t b = a + 1; b < cameras.size(); ++b) {
      EXPECT_GT(length(cameras[a].eye - cameras[b].eye) + length(cameras[a].up - cameras[b].up),
                1e-6);
    }
  }
  sweep.anglesPerAxis = 0;
  EXPECT_THROW(gpu::sweepCameras(model.patches, sweep), TesseraError);
}

TEST(ViewSweep, Table3StatisticsAreSane) {
  const LoadedModel& model = loadModel("bigguy");
  gpu::ViewSweep sweep;
  sweep.anglesPerAxis = 2;
  sweep.width = 640;
  sweep.height = 360;
  gpu::SweepStatistics small = gpu::sweepStatistics(model.patches, model.mesh.faceCount(), sweep);
  EXPECT_EQ(small.views, 4);
  EXPECT_GE(small.averageTrianglesPerBaseFace, 2.0)
      << "every face is at least one piece, 2 triangles";
  EXPECT_GE(small.averageRingDepth, 0.0);
  EXPECT_LE(small.averageRingDepth, small.maxRingDepth);
  EXPECT_GE(small.averageRingLevel, small.averageRingDepth);
  EXPECT_LE(small.averageRingLevel, small.maxRingLevel);
  EXPECT_GT(small.averagePieces, 0.0);
  // Twice the resolution halves the pixel in object space: more triangles, never shallower rings.
  sweep.width *= 2;
  sweep.height *= 2;
  gpu::SweepStatistics large = gpu::sweepStatistics(model.patches, model.mesh.faceCount(), sweep);
  EXPECT_GT(large.averageTrianglesPerBaseFace, small.averageTrianglesPerBaseFace);
  EXPECT_GE(large.averageRingDepth, small.averageRingDepth);
  std::printf(
      "[ measured ] bigguy, 4 views: %.1f triangles per base face at 640x360, %.1f at "
      "1280x720; ring depth avg %.2f max %d (Far level + FAS: avg %.2f max %d)\n",
      small.averageTrianglesPerBaseFace, large.averageTrianglesPerBaseFace, large.averageRingDepth,
      large.maxRingDepth, large.averageRingLevel, large.maxRingLevel);
  EXPECT_THROW(gpu::sweepStatistics(model.patches, 0, sweep), TesseraError);
}

}  // namespace
}  // namespace tessera::testing
