#include "core/bounds/diagonal_reparameterization.h"

#include <algorithm>

#include "core/math/bezier_net.h"

namespace tessera {

namespace {

constexpr int G = DiagonalMap::kCells;
constexpr double kParam[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

// The corners of each half of the pair, counter-clockwise: [diagonal][half].
constexpr int kHalfCorners[2][2][3] = {{{0, 1, 2}, {0, 2, 3}}, {{0, 1, 3}, {1, 2, 3}}};

// Parameter of the point of segment a → b nearest p, in [0, 1].
double nearestOnSegment(const Vec3d& p, const Vec3d& a, const Vec3d& b) {
  const double length2 = dot(b - a, b - a);
  return length2 > 0 ? std::clamp(dot(p - a, b - a) / length2, 0.0, 1.0) : 0.5;
}

// Where p projects onto the pair's half h, in the square's parameters (the least-squares
// barycentric coordinates, pulled into the triangle); false for a degenerate triangle.
bool projectOntoHalf(const Vec3d& p, const Vec3d corners[4], int diagonal, int h, double& u, double& v) {
  const int* k = kHalfCorners[diagonal][h];
  const Vec3d e1 = corners[k[1]] - corners[k[0]], e2 = corners[k[2]] - corners[k[0]], d = p - corners[k[0]];
  const double a = dot(e1, e1), b = dot(e1, e2), c = dot(e2, e2), det = a * c - b * b;
  if (!(det > 1e-12 * a * c)) return false;
  double s = std::max(0.0, (c * dot(e1, d) - b * dot(e2, d)) / det);
  double t = std::max(0.0, (a * dot(e2, d) - b * dot(e1, d)) / det);
  if (s + t > 1) s /= s + t, t = 1 - s;
  u = kParam[k[0]][0] + s * (kParam[k[1]][0] - kParam[k[0]][0]) + t * (kParam[k[2]][0] - kParam[k[0]][0]);
  v = kParam[k[0]][1] + s * (kParam[k[1]][1] - kParam[k[0]][1]) + t * (kParam[k[2]][1] - kParam[k[0]][1]);
  return true;
}

}  // namespace

DiagonalMap::GridLines DiagonalMap::evenLines() {
  GridLines lines;
  for (int i = 0; i <= G; ++i) lines[i] = double(i) / G;
  return lines;
}

DiagonalMap::DiagonalMap(int diagonal, const Vec3d corners[4], const Vec3d* grid, const GridLines& xs,
                         const GridLines& ys)
    : diagonal_(diagonal), xs_(xs), ys_(ys) {
  std::copy(corners, corners + 4, corners_.begin());
  // Where each grid point projects (its even position where it cannot move).
  std::array<double, kPoints * kPoints> pu, pv;
  for (int j = 0; j <= G; ++j) {
    for (int i = 0; i <= G; ++i) {
      const int n = i + kPoints * j;
      const Vec3d& f = grid[n];
      double u = double(i) / G, v = double(j) / G;
      const bool sideU = j == 0 || j == G, sideV = i == 0 || i == G;
      const bool onDiagonal = diagonal == 0 ? i == j : i + j == G;
      if (sideU && !sideV) {
        u = nearestOnSegment(f, corners[j == 0 ? 0 : 3], corners[j == 0 ? 1 : 2]);
      } else if (sideV && !sideU) {
        v = nearestOnSegment(f, corners[i == 0 ? 0 : 1], corners[i == 0 ? 3 : 2]);
      } else if (onDiagonal && !sideU) {
        const double t = nearestOnSegment(f, corners[diagonal == 0 ? 0 : 1], corners[diagonal == 0 ? 2 : 3]);
        u = diagonal == 0 ? t : 1 - t, v = t;
      } else if (!sideU) {
        projectOntoHalf(f, corners, diagonal, pairHalf(diagonal, u, v), u, v);
      }
      pu[n] = u, pv[n] = v;
    }
  }
  // The projections drawn back toward the identity until no grid triangle folds (τ = 0 always
  // keeps them all).
  // The even map sends the grid's diagonal onto the pair's and keeps every side: a bijection of
  // each half (monotone in each parameter), so the blend below ends at one.
  for (double tau = 1; tau > 0.1; tau /= 2) {
    for (int j = 0; j <= G; ++j) {
      for (int i = 0; i <= G; ++i) {
        const int n = i + kPoints * j;
        u_[n] = double(i) / G + tau * (pu[n] - double(i) / G);
        v_[n] = double(j) / G + tau * (pv[n] - double(j) / G);
      }
    }
    if (keepsOrientation()) {
      measureGridGap(grid);
      return;
    }
  }
  for (int j = 0; j <= G; ++j) {
    for (int i = 0; i <= G; ++i) u_[i + kPoints * j] = double(i) / G, v_[i + kPoints * j] = double(j) / G;
  }
  measureGridGap(grid);
}

void DiagonalMap::measureGridGap(const Vec3d* grid) {
  gridGap_ = 0;
  for (int n = 0; n < kPoints * kPoints; ++n) {
    const double u = u_[n], v = v_[n];
    gridGap_ = std::max(gridGap_, length(grid[n] - pairAt(corners_.data(), diagonal_, pairHalf(diagonal_, u, v), u, v)));
  }
}

// Every piece of ρ keeps its orientation: each split cell's two triangles turn counter-clockwise,
// and each other cell's bilinear map has a positive Jacobian at its four corners (it is affine in
// each parameter, so positive everywhere). With every side and the diagonal mapped onto
// themselves, ρ is then a bijection of each half onto the pair's half (a map of a disk, locally
// injective and one-to-one on the boundary).
bool DiagonalMap::keepsOrientation() const {
  constexpr double kMinArea = 1e-9 / (G * G);  // ρ's values are in the pair's square, ~1/G apart
  auto turn = [this](int a, int b, int c) {
    return (u_[b] - u_[a]) * (v_[c] - v_[a]) - (v_[b] - v_[a]) * (u_[c] - u_[a]);
  };
  for (int j = 0; j < G; ++j) {
    for (int i = 0; i < G; ++i) {
      const int corner[4] = {i + kPoints * j, i + 1 + kPoints * j, i + 1 + kPoints * (j + 1), i + kPoints * (j + 1)};
      if (!split(i, j)) {
        for (int k = 0; k < 4; ++k) {
          if (!(turn(corner[k], corner[(k + 1) % 4], corner[(k + 3) % 4]) > kMinArea)) return false;
        }
        continue;
      }
      for (int h = 0; h < 2; ++h) {
        const int* k = kHalfCorners[diagonal_][h];
        if (!(turn(corner[k[0]], corner[k[1]], corner[k[2]]) > kMinArea)) return false;
      }
    }
  }
  return true;
}

}  // namespace tessera
