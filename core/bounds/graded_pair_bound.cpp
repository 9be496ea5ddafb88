#include "core/bounds/graded_pair_bound.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/bounds/diagonal_pair_bound.h"
#include "core/bounds/diagonal_reparameterization.h"
#include "core/math/bicubic.h"

namespace tessera {

namespace {

constexpr int G = DiagonalMap::kCells;
constexpr int kSamples = 8;  // intervals the projection is sampled at along each axis

Vec3d at(const BezierNet& net, double u, double v) { return evaluateBezier(net.data(), u, v).position; }

// The surface on the (kSamples + 1)² grid of parameters (m, n) / kSamples, index m + (kSamples + 1) n.
using Samples = std::array<Vec3d, (kSamples + 1) * (kSamples + 1)>;

// Grid lines for diagonal d whose staircase of grid points (xs[i], ys[i]) (diagonal 0) or
// (xs[i], ys[G − i]) (diagonal 1), the points ρ sends onto the pair's diagonal D, lie where the
// surface comes nearest D's points at i / G along it: the surface's own fold line, which the
// even grid's diagonal follows only when the parameterization is even. Any increasing lines give
// a valid bound (§3c); false when the nearest sample points do not increase (the even lines then).
bool foldLines(const Samples& f, const Vec3d corners[4], int d, DiagonalMap::GridLines& xs,
               DiagonalMap::GridLines& ys) {
  xs = ys = DiagonalMap::evenLines();
  const Vec3d from = corners[d == 0 ? 0 : 1], to = corners[d == 0 ? 2 : 3];
  int lastM = 0, lastN = d == 0 ? 0 : kSamples;
  for (int i = 1; i < G; ++i) {
    const Vec3d target = from + (to - from) * (d == 0 ? double(i) / G : 1 - double(i) / G);
    int best = 0;
    double nearest = length(f[0] - target);
    for (int k = 1; k < int(f.size()); ++k) {
      const double distance = length(f[k] - target);
      if (distance < nearest) best = k, nearest = distance;
    }
    const int m = best % (kSamples + 1), n = best / (kSamples + 1);
    const bool increasing = m > lastM && (d == 0 ? n > lastN : n < lastN);
    if (!increasing || m == kSamples || n == 0 || n == kSamples) return false;
    xs[i] = double(m) / kSamples;
    ys[d == 0 ? i : G - i] = double(n) / kSamples;
    lastM = m, lastN = n;
  }
  return true;
}

// The surface on the sample grid: each row of the net contracted along u at every sample, then
// the four curves along v (tensor product, ~4 multiply-adds a point and coordinate).
Samples sampleNet(const BezierNet& net) {
  std::array<std::array<double, 4>, kSamples + 1> w;
  for (int m = 0; m <= kSamples; ++m) {
    double dw[4];
    cubicBernstein(double(m) / kSamples, w[m].data(), dw);
  }
  std::array<Vec3d, 4 * (kSamples + 1)> rows;  // rows[row * (kSamples + 1) + m]
  for (int row = 0; row < 4; ++row) {
    for (int m = 0; m <= kSamples; ++m) {
      Vec3d p;
      for (int col = 0; col < 4; ++col) p += net[4 * row + col] * w[m][col];
      rows[row * (kSamples + 1) + m] = p;
    }
  }
  Samples f;
  for (int n = 0; n <= kSamples; ++n) {
    for (int m = 0; m <= kSamples; ++m) {
      Vec3d p;
      for (int row = 0; row < 4; ++row) p += rows[row * (kSamples + 1) + m] * w[n][row];
      f[m + (kSamples + 1) * n] = p;
    }
  }
  return f;
}

// The graded map for diagonal d (even lines where the fold lines do not increase).
DiagonalMap gradedMap(const BezierNet& net, const Samples& f, const Vec3d corners[4], int d) {
  DiagonalMap::GridLines xs, ys;
  if (!foldLines(f, corners, d, xs, ys)) xs = ys = DiagonalMap::evenLines();
  Vec3d grid[DiagonalMap::kPoints * DiagonalMap::kPoints];
  for (int j = 0; j <= G; ++j) {
    for (int i = 0; i <= G; ++i) grid[i + DiagonalMap::kPoints * j] = at(net, xs[i], ys[j]);
  }
  return DiagonalMap(d, corners, grid, xs, ys);
}

}  // namespace

std::optional<PairBounds> gradedPairBounds(const BezierNet& net, double below, double abortAbove) {
  Vec3d corners[4];
  for (int k = 0; k < 4; ++k) corners[k] = net[kCornerIndex[k]];
  const Samples f = sampleNet(net);
  const DiagonalMap first = gradedMap(net, f, corners, 0), second = gradedMap(net, f, corners, 1);
  const DiagonalMap& map = second.gridGap() < first.gridGap() ? second : first;
  // The gap at the grid points is a lower bound of the result: no use bounding the rest.
  if (!(map.gridGap() < below) || map.gridGap() > abortAbove) return std::nullopt;
  LeafOwn own{{corners[0], corners[1], corners[2], corners[3]}, 0, 0, 1, splitNetDistance(net, bilinearNet(corners)), {}};
  const std::array<double, 4> bows = chordBows(net, corners);
  std::copy(bows.begin(), bows.end(), own.bows);
  PairBounds out;
  out.pair = map.gridGap();  // starts the maximum, so cheap bounds skip more
  const LazyNet whole(net);
  pieceAgainstDiagonal(&whole, 0, own, 0, 0, 1, map, out.pair, out.bows, abortAbove);
  if (out.pair > abortAbove) return std::nullopt;
  out.diagonal = uint8_t(1 + map.diagonal());
  return out;
}

double pairLowerBound(const BezierNet& net) {
  const Vec3d c[4] = {net[kCornerIndex[0]], net[kCornerIndex[1]], net[kCornerIndex[2]], net[kCornerIndex[3]]};
  return pairLowerBound(c, at(net, 0.5, 0.5));
}

double pairLowerBound(const Vec3d c[4], const Vec3d& centre) {
  // Distance from the centre to the plane through three corners, at most its distance to their
  // triangle (0 for a degenerate triangle: no plane to measure from).
  auto plane = [&](int a, int b, int d) {
    const Vec3d n = cross(c[b] - c[a], c[d] - c[a]);
    const double area = length(n);
    return area > 0 ? std::abs(dot(centre - c[a], n)) / area : 0.0;
  };
  const double along0 = std::min(plane(0, 1, 2), plane(0, 2, 3)), along1 = std::min(plane(0, 1, 3), plane(1, 2, 3));
  return std::min(along0, along1);
}

}  // namespace tessera
