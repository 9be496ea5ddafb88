#include "core/bounds/axis_reparameterization.h"

#include <cmath>

namespace tessera {

namespace {

// Breakpoints whose preimages come closer than this are dropped: α stays a bijection with a
// bounded slope (every cell at least 1/4096 wide in t).
constexpr double kMinStep = 1.0 / 4096;

}  // namespace

AxisMap::AxisMap() {
  for (int m = 0; m <= kCells; ++m) t_[m] = double(m) / kCells;
}

double AxisMap::preimage(double x) const {
  if (identity_) return x;
  const double scaled = x * kCells;
  int m = int(scaled);
  if (m >= kCells) m = kCells - 1;
  return t_[m] + (scaled - m) * (t_[m + 1] - t_[m]);
}

void AxisMapBuilder::addPiece(double x0, double x1) {
  const double a = x0 * AxisMap::kCells, b = x1 * AxisMap::kCells;
  for (int m = int(std::floor(a)) + 1; m < b && m < AxisMap::kCells; ++m) spanned_ |= uint64_t(1) << m;
}

void AxisMapBuilder::addSample(double x, double t) {
  const double scaled = x * AxisMap::kCells;
  const int m = int(scaled);
  if (m <= 0 || m >= AxisMap::kCells || double(m) != scaled) return;
  sum_[m] += t;
  ++count_[m];
}

AxisMap AxisMapBuilder::build() const {
  AxisMap map;
  int last = 0;
  double lastT = 0;
  for (int m = 1; m <= AxisMap::kCells; ++m) {
    double t = 1;
    if (m < AxisMap::kCells) {
      if ((spanned_ >> m & 1) || count_[m] == 0) continue;
      t = sum_[m] / count_[m];
      if (!(t > lastT + kMinStep && t < 1 - kMinStep)) continue;
    }
    for (int k = last + 1; k <= m; ++k) map.t_[k] = lastT + (t - lastT) * double(k - last) / double(m - last);
    if (m < AxisMap::kCells) map.identity_ = false;
    last = m;
    lastT = t;
  }
  return map;
}

}  // namespace tessera
