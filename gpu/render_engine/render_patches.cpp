#include "gpu/render_engine/render_patches.h"

#include <array>
#include <cmath>

namespace tessera::gpu {
namespace {

using Cubic = std::array<Vec3d, 4>;

// de Casteljau at t = 1/2. The shared midpoint is computed once and copied into both halves,
// so neighbouring sub-pieces see the same bits on their common edge.
void halve(const Cubic& c, Cubic& left, Cubic& right) {
  Vec3d p01 = (c[0] + c[1]) * 0.5, p12 = (c[1] + c[2]) * 0.5, p23 = (c[2] + c[3]) * 0.5;
  Vec3d p012 = (p01 + p12) * 0.5, p123 = (p12 + p23) * 0.5;
  Vec3d mid = (p012 + p123) * 0.5;
  left = {c[0], p01, p012, mid};
  right = {mid, p123, p23, c[3]};
}

// The 2^k cubic segments of [i, i+1]/2^k, in order, by repeated halving.
std::vector<Cubic> segments(const Cubic& curve, int k) {
  std::vector<Cubic> current{curve};
  for (int level = 0; level < k; ++level) {
    std::vector<Cubic> next(2 * current.size());
    for (size_t i = 0; i < current.size(); ++i) halve(current[i], next[2 * i], next[2 * i + 1]);
    current.swap(next);
  }
  return current;
}

int ceilDivPow2(int level, int k) {
  return int((int64_t(level) + (int64_t(1) << k) - 1) >> k);
}

}  // namespace

int splitCount(int level) {
  int k = 0;
  while (ceilDivPow2(level, k) > int(kMaxTessellationLevel)) ++k;
  return k;
}

int64_t renderedTriangles(int level) {
  int k = splitCount(level);
  int64_t sub = std::max(ceilDivPow2(level, k), 1);
  return (int64_t(1) << (2 * k)) * 2 * sub * sub;
}

void appendRenderPatches(const BezierPiece& piece, uint32_t patchId,
                         std::vector<RenderPatch>& out) {
  const int k = splitCount(piece.level);
  const uint32_t level = uint32_t(std::max(ceilDivPow2(piece.level, k), 1));
  auto emit = [&](auto&& controlPoint) {
    RenderPatch patch{};
    for (int p = 0; p < 16; ++p) {
      Vec3 c = controlPoint(p);
      patch.controlPoints[p][0] = c.x;
      patch.controlPoints[p][1] = c.y;
      patch.controlPoints[p][2] = c.z;
    }
    for (uint32_t& e : patch.edgeLevels) e = level;
    patch.patchId = patchId;
    out.push_back(patch);
  };
  if (k == 0) {
    emit([&](int p) { return piece.bezier[p]; });
    return;
  }
  const int n = 1 << k;
  // Rows (constant t) split along s first; then each column of every s-strip along t.
  std::array<std::vector<Cubic>, 4> rows;
  for (int r = 0; r < 4; ++r) {
    Cubic row;
    for (int c = 0; c < 4; ++c) row[c] = Vec3d(piece.bezier[4 * r + c]);
    rows[r] = segments(row, k);
  }
  std::vector<std::array<std::vector<Cubic>, 4>> columns(n);  // [i][c] -> segments along t
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 4; ++c) {
      Cubic column{rows[0][i][c], rows[1][i][c], rows[2][i][c], rows[3][i][c]};
      columns[i][c] = segments(column, k);
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      emit([&](int p) { return Vec3(columns[i][p % 4][j][p / 4]); });
    }
  }
}

ViewFrustum::ViewFrustum(const tessera::Camera& camera) : eye_(camera.eye) {
  Vec3d view = camera.target - camera.eye;
  forward_ = view * (1.0 / length(view));
  right_ = cross(forward_, camera.up);
  right_ = right_ * (1.0 / length(right_));
  up_ = cross(right_, forward_);
  constexpr double kGuardBand = 1.01;
  tanY_ = std::tan(camera.fovYDegrees * M_PI / 360.0) * kGuardBand;
  tanX_ = std::tan(camera.fovYDegrees * M_PI / 360.0) * camera.width / camera.height * kGuardBand;
}

bool ViewFrustum::mayShow(const Vec3* points, int count) const {
  // Outside bits per point: behind the eye, left, right, below, above (planes through the eye).
  unsigned common = 0x1F;
  for (int i = 0; i < count && common != 0; ++i) {
    Vec3d d = Vec3d(points[i]) - eye_;
    double z = dot(d, forward_), x = dot(d, right_), y = dot(d, up_);
    unsigned outside = (z <= 0 ? 1u : 0u) | (x < -z * tanX_ ? 2u : 0u) | (x > z * tanX_ ? 4u : 0u) |
                       (y < -z * tanY_ ? 8u : 0u) | (y > z * tanY_ ? 16u : 0u);
    common &= outside;
  }
  return common == 0;
}

}  // namespace tessera::gpu
