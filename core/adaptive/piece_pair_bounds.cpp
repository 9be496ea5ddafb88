#include "core/adaptive/piece_pair_bounds.h"

#include <array>

namespace tessera {

double exactPairBound(const BezierNet& net) {
  Vec3d corners[4];
  for (int c = 0; c < 4; ++c) corners[c] = net[kCornerIndex[c]];
  const Vec3d twist = corners[0] - corners[1] + corners[2] - corners[3];
  return (splitNetDistance(net, bilinearNet(corners)) + length(twist) / 4) * (1 + 1e-9);
}

void exactSideBows(const BezierNet& net, double bows[4]) {
  Vec3d corners[4];
  for (int c = 0; c < 4; ++c) corners[c] = net[kCornerIndex[c]];
  const std::array<double, 4> chord = chordBows(net, corners);
  for (int side = 0; side < 4; ++side) bows[side] = chord[side] * (1 + 1e-9);
}

double centreGap(const BezierNet& net) {
  static constexpr double kWeight[4] = {1 / 8.0, 3 / 8.0, 3 / 8.0, 1 / 8.0};
  Vec3d centre;
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) centre += net[4 * row + col] * (kWeight[row] * kWeight[col]);
  }
  Vec3d bilinear;
  for (int c = 0; c < 4; ++c) bilinear += net[kCornerIndex[c]] * 0.25;
  return length(centre - bilinear);
}

}  // namespace tessera
