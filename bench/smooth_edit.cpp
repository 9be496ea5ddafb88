#include "bench/smooth_edit.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tessera::bench {

SmoothEdit::SmoothEdit(const ControlMesh& rest) : rest_(rest.positions) {
  if (rest_.empty()) return;
  Vec3d lo(rest_[0]), hi(rest_[0]);
  for (const Vec3& p : rest_) {
    lo = Vec3d(std::min(lo.x, double(p.x)), std::min(lo.y, double(p.y)),
               std::min(lo.z, double(p.z)));
    hi = Vec3d(std::max(hi.x, double(p.x)), std::max(hi.y, double(p.y)),
               std::max(hi.z, double(p.z)));
  }
  diagonal_ = length(hi - lo);
}

void SmoothEdit::apply(int64_t frame, std::vector<Vec3>& moved) const {
  // One wavelength over the diagonal keeps the field's curvature far below the surface's own,
  // so the edit bends the shape without adding detail a tolerance would have to follow. Each
  // axis's sine runs along the sum of the other two coordinates (a shear that varies in space,
  // not a translation) and has its own phase speed, so frames never repeat.
  const double wave = 2 * std::numbers::pi / std::max(diagonal_, 1e-30);
  const double reach =
      kRelativeAmplitude * diagonal_ / std::sqrt(3.0);  // |field| ≤ 1 % of the diagonal
  const double t = double(frame);
  const double phase[3] = {0.9 * t, 1.3 * t + 2.0, 0.7 * t + 4.0};
  moved.resize(rest_.size());
  for (size_t i = 0; i < rest_.size(); ++i) {
    const Vec3d p(rest_[i]);
    const Vec3d shift(std::sin(wave * (p.y + p.z) + phase[0]),
                      std::sin(wave * (p.z + p.x) + phase[1]),
                      std::sin(wave * (p.x + p.y) + phase[2]));
    moved[i] = Vec3(p + shift * reach);
  }
}

}  // namespace tessera::bench
