// A reparameterization of a node's square for the twist-free pair bound (docs/ADAPTIVE.md §3b):
// the two triangles through the node's corners, split along one diagonal, compared with
// f ∘ φ where φ⁻¹ = ρ is piecewise bilinear on a kCells × kCells grid that keeps every side and
// that diagonal in place; the cells on the grid's own diagonal are split along it into two linear
// triangles, and ρ sends that staircase of grid points onto the pair's diagonal. Each cell (or
// triangle) then maps into one triangle of the pair, so the pair composed with ρ is bilinear (or
// affine) over it: a piece's net against it is a convex-hull bound. The grid's lines need not be
// evenly spaced (GridLines): graded toward where the parameterization crowds, a few cells follow
// what an even grid would need many for (docs/ADAPTIVE.md §3c).
#pragma once

#include <array>

#include "core/base/vec3.h"
#include "core/math/bezier_net.h"

namespace tessera {

// The triangle pair over the unit square (corners counter-clockwise from (0, 0)) split along
// diagonal 0 (corners 0–2) or 1 (corners 1–3). Half 0 is the triangle holding side 0 (v = 0).
inline int pairHalf(int diagonal, double a, double b) { return diagonal == 0 ? (a >= b ? 0 : 1) : (a + b <= 1 ? 0 : 1); }

// The linear interpolant of c over `half` at (a, b); outside the half, its plane extended.
template <class T>
T pairAt(const T c[4], int diagonal, int half, double a, double b) {
  if (diagonal == 0) return half == 0 ? c[0] + (c[1] - c[0]) * a + (c[2] - c[1]) * b : c[0] + (c[2] - c[3]) * a + (c[3] - c[0]) * b;
  return half == 0 ? c[0] + (c[1] - c[0]) * a + (c[3] - c[0]) * b
                   : c[2] + (c[2] - c[3]) * (a - 1) + (c[2] - c[1]) * (b - 1);
}

class DiagonalMap {
 public:
  static constexpr int kCells = 4;
  static constexpr int kPoints = kCells + 1;
  // Grid lines along one axis: 0 = x_0 < x_1 < … < x_kCells = 1, each a dyadic fraction, so that
  // a piece halved often enough lies in one cell.
  using GridLines = std::array<double, kPoints>;
  static GridLines evenLines();

  // ρ for the pair over `corners` (f at the square's corners) along `diagonal`, from f at the grid
  // points (xs[i], ys[j]), index i + kPoints j: each point goes where it projects onto the pair
  // (side points onto their chord, the grid's diagonal onto the pair's), drawn back toward the
  // even map (grid point (i, j) to (i, j) / kCells) until every grid triangle keeps its orientation.
  DiagonalMap(int diagonal, const Vec3d corners[4], const Vec3d* grid, const GridLines& xs = evenLines(),
              const GridLines& ys = evenLines());

  int diagonal() const { return diagonal_; }
  // max ‖f − pair ∘ ρ‖ over the grid points: a lower bound of the sup the map is for.
  double gridGap() const { return gridGap_; }

  // The cell holding [x, x + s] along u (column) and along v (row); whether the square crosses a
  // grid line.
  int column(double x) const { return cellOf(xs_, x); }
  int row(double y) const { return cellOf(ys_, y); }
  bool spans(double x, double y, double s) const;
  // The square's side over the cell's smaller side.
  double relativeSize(int i, int j, double s) const {
    return s / std::min(xs_[i + 1] - xs_[i], ys_[j + 1] - ys_[j]);
  }

  // Which triangles of cell (i, j) the square [x, x + s] × [y, y + s] (node units, inside the
  // cell) meets with positive area: bit h for the cell's half h (its own diagonal parallel to
  // the pair's); 1 for a cell the diagonal does not cross (one bilinear piece, "half" 0).
  int trianglesMet(int i, int j, double x, double y, double s) const;

  // The pair at ρ(x, y), ρ taken as over half h of cell (i, j) (extended outside it), the pair as
  // over the half that piece maps into: bilinear in (x, y), affine in a split cell.
  Vec3d pairOverTriangle(int i, int j, int h, double x, double y) const;

  // The pair at ρ(x, y) for a point on the square's boundary (exact: ρ keeps every side).
  Vec3d pairOnBoundary(double x, double y) const;

 private:
  static int cellOf(const GridLines& lines, double x);
  bool split(int i, int j) const;
  void local(int i, int j, double x, double y, double& a, double& b) const;
  int imageHalf(int i, int j, int h) const;
  void imageOf(int i, int j, int h, double x, double y, double& u, double& v) const;
  bool keepsOrientation() const;
  void measureGridGap(const Vec3d* grid);

  int diagonal_;
  double gridGap_ = 0;
  std::array<Vec3d, 4> corners_;
  GridLines xs_, ys_;
  std::array<double, kPoints * kPoints> u_, v_;  // ρ at the grid points
};

// The per-square queries, inline: the §3b walk asks them ~10⁵ times a plan.

inline int DiagonalMap::cellOf(const GridLines& lines, double x) {
  int i = 0;
  while (i + 1 < kCells && x >= lines[i + 1]) ++i;
  return i;
}

inline bool DiagonalMap::spans(double x, double y, double s) const {
  const int i = column(x), j = row(y);
  return x + s > xs_[i + 1] || y + s > ys_[j + 1];
}

inline bool DiagonalMap::split(int i, int j) const { return diagonal_ == 0 ? i == j : i + j + 1 == kCells; }

// (x, y) in cell (i, j)'s own unit square.
inline void DiagonalMap::local(int i, int j, double x, double y, double& a, double& b) const {
  a = (x - xs_[i]) / (xs_[i + 1] - xs_[i]), b = (y - ys_[j]) / (ys_[j + 1] - ys_[j]);
}

inline int DiagonalMap::trianglesMet(int i, int j, double x, double y, double s) const {
  if (!split(i, j)) return 1;
  double a, b;
  local(i, j, x, y, a, b);
  const double ta = s / (xs_[i + 1] - xs_[i]), tb = s / (ys_[j + 1] - ys_[j]);
  if (diagonal_ == 0) return (a + ta > b ? 1 : 0) | (b + tb > a ? 2 : 0);
  return (a + b < 1 ? 1 : 0) | (a + ta + b + tb > 1 ? 2 : 0);
}

// The pair's half that half h of cell (i, j) maps into: the cells off the diagonal lie wholly in
// one half, those on it are split by it.
inline int DiagonalMap::imageHalf(int i, int j, int h) const {
  if (diagonal_ == 0) return i > j ? 0 : i < j ? 1 : h;
  return i + j + 1 < kCells ? 0 : i + j + 1 > kCells ? 1 : h;
}

inline void DiagonalMap::imageOf(int i, int j, int h, double x, double y, double& u, double& v) const {
  const int n = i + kPoints * j;
  const double cu[4] = {u_[n], u_[n + 1], u_[n + 1 + kPoints], u_[n + kPoints]};
  const double cv[4] = {v_[n], v_[n + 1], v_[n + 1 + kPoints], v_[n + kPoints]};
  double a, b;
  local(i, j, x, y, a, b);
  if (!split(i, j)) {
    u = bilinearAt(cu, a, b), v = bilinearAt(cv, a, b);
    return;
  }
  u = pairAt(cu, diagonal_, h, a, b), v = pairAt(cv, diagonal_, h, a, b);
}

inline Vec3d DiagonalMap::pairOverTriangle(int i, int j, int h, double x, double y) const {
  double u, v;
  imageOf(i, j, h, x, y, u, v);
  return pairAt(corners_.data(), diagonal_, imageHalf(i, j, h), u, v);
}

inline Vec3d DiagonalMap::pairOnBoundary(double x, double y) const {
  const int i = column(x), j = row(y);
  double a, b, u, v;
  local(i, j, x, y, a, b);
  imageOf(i, j, pairHalf(diagonal_, a, b), x, y, u, v);
  return pairAt(corners_.data(), diagonal_, pairHalf(diagonal_, u, v), u, v);
}

}  // namespace tessera
