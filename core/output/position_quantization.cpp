#include "core/output/position_quantization.h"

#include <algorithm>
#include <cmath>

namespace tessera {

namespace {
// The box spans ±kHalfRange steps: 32767 is int16's largest, and one step short of it leaves a
// margin for vertices rounded a float ulp outside the box.
constexpr double kHalfRange = 32765;
}  // namespace

PositionQuantization quantizationForBox(const Vec3& lo, const Vec3& hi) {
  const Vec3d low(lo), high(hi);
  const Vec3d half = (high - low) * 0.5;
  const double largest = std::max({half.x, half.y, half.z});
  PositionQuantization q;
  q.center = Vec3d(Vec3((low + high) * 0.5));
  // Rounded up to a float so every box point stays within kHalfRange + ½ steps of the centre.
  q.step = largest > 0 ? double(std::nextafter(float(largest / kHalfRange), INFINITY)) : 1.0;
  const double reach =
      std::max({std::abs(q.center.x), std::abs(q.center.y), std::abs(q.center.z)}) + largest;
  q.maxError = std::sqrt(3.0) * (0.5 * q.step + std::ldexp(reach, -23));
  // Far from the origin a float ulp of a coordinate can pass the margin of 1.5 steps beyond the
  // box: such a box has no usable grid (and float positions are what it can have).
  if (std::ldexp(reach, -23) > q.step) q.maxError = INFINITY;
  return q;
}

std::array<int16_t, 3> PositionQuantization::quantize(const Vec3& p) const {
  auto axis = [this](double value, double centre) {
    return int16_t(std::clamp(std::nearbyint((value - centre) / step), -32767.0, 32767.0));
  };
  return {axis(p.x, center.x), axis(p.y, center.y), axis(p.z, center.z)};
}

Vec3 PositionQuantization::dequantize(const std::array<int16_t, 3>& q) const {
  const float s = float(step);
  return Vec3(float(center.x) + s * float(q[0]), float(center.y) + s * float(q[1]),
              float(center.z) + s * float(q[2]));
}

}  // namespace tessera
