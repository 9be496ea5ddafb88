// Pieces → render patches without a device: levels, splitting by de Casteljau, the frustum test
// and the camera conversion.
#include "gpu/render_engine/render_patches.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <random>

#include "core/base/error.h"
#include "gpu/render_engine/camera_conversion.h"

namespace tessera::gpu {
namespace {

BezierPiece randomPiece(int level, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
  BezierPiece piece;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      piece.bezier[size_t(4 * j + i)] = Vec3(i + jitter(rng), j + jitter(rng), jitter(rng) * 3);
    }
  }
  piece.level = level;
  return piece;
}

// Bernstein evaluation in double, written here (independent of core/math/bicubic.h).
Vec3d evaluate(const float (*cp)[3], double u, double v) {
  auto basis = [](double t, double w[4]) {
    double s = 1 - t;
    w[0] = s * s * s, w[1] = 3 * t * s * s, w[2] = 3 * t * t * s, w[3] = t * t * t;
  };
  double wu[4], wv[4];
  basis(u, wu);
  basis(v, wv);
  Vec3d p;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i)
      p += Vec3d(cp[4 * j + i][0], cp[4 * j + i][1], cp[4 * j + i][2]) * (wu[i] * wv[j]);
  }
  return p;
}

TEST(RenderPatches, SplitCountKeepsLevelsWithinTheRenderersLimit) {
  EXPECT_EQ(splitCount(1), 0);
  EXPECT_EQ(splitCount(64), 0);
  EXPECT_EQ(splitCount(65), 1);
  EXPECT_EQ(splitCount(128), 1);
  EXPECT_EQ(splitCount(129), 2);
  EXPECT_EQ(splitCount(1'000'000), 14);
  for (int level : {1, 7, 64, 65, 100, 128, 129, 4096, 1'000'000}) {
    int k = splitCount(level);
    int sub = int((int64_t(level) + (1 << k) - 1) >> k);
    EXPECT_LE(sub, int(kMaxTessellationLevel)) << level;
    EXPECT_GE(sub << k, level) << "the sub-pieces' grid must be at least as fine: " << level;
    EXPECT_EQ(renderedTriangles(level), (int64_t(1) << (2 * k)) * 2 * int64_t(sub) * sub);
  }
}

TEST(RenderPatches, UnsplitPieceKeepsItsControlPointsAndLevelOnEveryEdge) {
  BezierPiece piece = randomPiece(17, 1);
  std::vector<RenderPatch> out;
  appendRenderPatches(piece, 42, out);
  ASSERT_EQ(out.size(), 1u);
  for (int p = 0; p < 16; ++p) {
    EXPECT_EQ(out[0].controlPoints[p][0], piece.bezier[size_t(p)].x);
    EXPECT_EQ(out[0].controlPoints[p][1], piece.bezier[size_t(p)].y);
    EXPECT_EQ(out[0].controlPoints[p][2], piece.bezier[size_t(p)].z);
  }
  for (uint32_t e : out[0].edgeLevels) EXPECT_EQ(e, 17u);
  EXPECT_EQ(out[0].patchId, 42u);
}

TEST(RenderPatches, SplitSubPiecesReproduceThePieceAndShareEdgesBitForBit) {
  BezierPiece piece = randomPiece(200, 2);  // k = 2: 4×4 sub-pieces at level 50
  std::vector<RenderPatch> out;
  appendRenderPatches(piece, 7, out);
  ASSERT_EQ(out.size(), 16u);
  float parent[16][3];
  for (int p = 0; p < 16; ++p) {
    parent[p][0] = piece.bezier[size_t(p)].x, parent[p][1] = piece.bezier[size_t(p)].y,
    parent[p][2] = piece.bezier[size_t(p)].z;
  }
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      const RenderPatch& sub = out[size_t(4 * j + i)];
      for (uint32_t e : sub.edgeLevels) EXPECT_EQ(e, 50u);
      EXPECT_EQ(sub.patchId, 7u);
      // Same surface: sub-piece (i, j) at (a, b) is the piece at ((i + a)/4, (j + b)/4). The
      // control points are rounded to float once, so agreement is to float precision.
      for (double a : {0.0, 0.3, 1.0}) {
        for (double b : {0.0, 0.7, 1.0}) {
          Vec3d x = evaluate(sub.controlPoints, a, b);
          Vec3d y = evaluate(parent, (i + a) / 4, (j + b) / 4);
          EXPECT_LT(length(x - y), 1e-5) << i << "," << j << " at " << a << "," << b;
        }
      }
      // Shared boundaries: the right column of (i, j) is the left column of (i + 1, j), the
      // top row of (i, j) the bottom row of (i, j + 1), bit for bit.
      for (int r = 0; r < 4; ++r) {
        if (i + 1 < 4) {
          EXPECT_EQ(0, std::memcmp(sub.controlPoints[4 * r + 3],
                                   out[size_t(4 * j + i + 1)].controlPoints[4 * r], 12));
        }
        if (j + 1 < 4) {
          EXPECT_EQ(0, std::memcmp(sub.controlPoints[12 + r],
                                   out[size_t(4 * (j + 1) + i)].controlPoints[r], 12));
        }
      }
    }
  }
}

TEST(ViewFrustum, KeepsWhatTouchesTheViewAndDropsWhatIsBehindOrBeside) {
  tessera::Camera camera;
  camera.eye = {0, 0, 10};
  camera.target = {0, 0, 0};
  camera.fovYDegrees = 40;
  camera.width = 200;
  camera.height = 100;
  ViewFrustum frustum(camera);
  auto box = [](Vec3 lo, Vec3 hi) {
    std::array<Vec3, 8> p;
    for (int c = 0; c < 8; ++c)
      p[size_t(c)] = Vec3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
    return p;
  };
  EXPECT_TRUE(frustum.mayShow(box({-1, -1, -1}, {1, 1, 1}).data(), 8));
  EXPECT_FALSE(frustum.mayShow(box({-1, -1, 11}, {1, 1, 12}).data(), 8)) << "behind the eye";
  // The view's half-height at distance d is d·tan 20° ≈ 0.364·d (4.04 at the far side of the
  // boxes, d = 11, with the 1% guard band), its half-width twice that.
  EXPECT_FALSE(frustum.mayShow(box({-1, 4.5f, -1}, {1, 5, 1}).data(), 8)) << "above";
  EXPECT_TRUE(frustum.mayShow(box({-1, 3.0f, -1}, {1, 5, 1}).data(), 8)) << "straddles the top";
  EXPECT_FALSE(frustum.mayShow(box({8.5f, -1, -1}, {9, 1, 1}).data(), 8)) << "right";
  EXPECT_TRUE(frustum.mayShow(box({6.5f, -1, -1}, {9, 1, 1}).data(), 8)) << "straddles the right";
  // Points outside different planes do not make a hull outside the view.
  Vec3 apart[2] = {Vec3(-20, 0, 0), Vec3(20, 0, 0)};
  EXPECT_TRUE(frustum.mayShow(apart, 2));
}

TEST(CameraConversion, KeepsEveryFieldInSinglePrecision) {
  tessera::Camera core;
  core.eye = {1, 2, 3};
  core.target = {-1, 0.5, 0.1};
  core.up = {0, 0, 1};
  core.fovYDegrees = 33;
  core.width = 640;
  core.height = 480;
  Camera gpu = toGpuCamera(core);
  EXPECT_EQ(gpu.eye.x, 1.0f);
  EXPECT_EQ(gpu.eye.y, 2.0f);
  EXPECT_EQ(gpu.target.z, 0.1f);  // the float nearest 0.1
  EXPECT_EQ(gpu.up.z, 1.0f);
  EXPECT_EQ(gpu.fovYDegrees, 33.0f);
  EXPECT_EQ(gpu.width, 640u);
  EXPECT_EQ(gpu.height, 480u);
  EXPECT_EQ(gpu.nearPlane, 0.0f);
  EXPECT_EQ(gpu.farPlane, 0.0f);
}

}  // namespace
}  // namespace tessera::gpu
