// Planar scenes of two patches sharing one curved edge, for the shared-edge and crack tests.
// Both patches lie in z = 0 and together cover exactly the square [-1,1]² (their shared
// boundary is the cubic x = 3b·t(1−t), y = 2t − 1). The right patch is parameterised
// backwards (u and v reversed), so the shared edge runs in opposite directions on the two
// sides, as it does between consistently oriented neighbours.
#pragma once

#include <vector>

#include "render_test_support.h"

namespace tessera::gpu::testing {

inline constexpr uint32_t kLeftId = 7;
inline constexpr uint32_t kRightId = 8;
inline constexpr uint32_t kBackId = 99;

// sharedLeft/sharedRight: each side's level for the shared edge (equal for a watertight seam).
inline std::vector<RenderPatch> twoPatchesWithCurvedSeam(double bulge, uint32_t sharedLeft,
                                                         uint32_t sharedRight) {
  const double seamX[4] = {0.0, bulge, bulge, 0.0};
  ControlNet left, right;
  for (int j = 0; j < 4; ++j) {
    double y = -1.0 + 2.0 * j / 3.0;
    for (int i = 0; i < 4; ++i) {
      double s = i / 3.0;
      left[4 * j + i] = Vec3d(-1.0 + s * (seamX[j] + 1.0), y, 0.0);
      // Forward right patch Q(i, j) = seam + s·(1 − seam); stored reversed: R(i,j) = Q(3−i, 3−j).
      right[4 * (3 - j) + (3 - i)] = Vec3d(seamX[j] + s * (1.0 - seamX[j]), y, 0.0);
    }
  }
  // Interior levels differ on purpose (7 vs 9 across, 4 vs 5 up), so both sides stitch.
  return {makePatch(left, {7, sharedLeft, 2, 4}, kLeftId),
          makePatch(right, {3, sharedRight, 9, 5}, kRightId)};
}

// A plane at z = −0.5 behind the pair, larger than it: what a crack in the pair would show.
inline RenderPatch backPlane() {
  return makePatch(planarNet(Vec3d(-1.5, -1.5, -0.5), Vec3d(3, 0, 0), Vec3d(0, 3, 0)), {4, 4, 4, 4},
                   kBackId);
}

// Straight down the z axis; the square spans about 176 px of the 256 px image.
inline Camera topDownCamera(uint32_t size = 256) {
  Camera camera;
  camera.eye = Vec3(0.0f, 0.0f, 4.0f);
  camera.target = Vec3(0.0f, 0.0f, 0.0f);
  camera.fovYDegrees = 40.0f;
  camera.width = size;
  camera.height = size;
  return camera;
}

// Pixels whose centre lies in the square [-1,1]² shrunk by `inset` (world units) but that
// show something other than the pair (background or the back plane).
inline size_t pixelsNotShowingPair(const Frame& frame, const Camera& camera, double inset) {
  Pinhole pinhole(camera);
  size_t count = 0;
  for (uint32_t y = 0; y < frame.height; ++y) {
    for (uint32_t x = 0; x < frame.width; ++x) {
      Vec3d hit;
      if (!pinhole.hitPlaneZ(x, y, 0.0, hit)) continue;
      if (std::abs(hit.x) > 1.0 - inset || std::abs(hit.y) > 1.0 - inset) continue;
      uint32_t id = frame.patchIdAt(x, y);
      count += id != kLeftId && id != kRightId;
    }
  }
  return count;
}

}  // namespace tessera::gpu::testing
