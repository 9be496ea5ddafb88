// Uniform bicubic B-spline and Bézier patches: basis functions, the B-spline → Bézier change of
// basis (MATH.md §2: Bez = M·B·Mᵀ) and evaluation with first derivatives. Control points are
// row-major, index 4*row + col, col along s (u), row along t (v).
#pragma once

#include "core/base/host_device.h"
#include "core/base/vec3.h"
#include "core/math/cubic_bernstein.h"

namespace tessera {

template <typename T>
TESSERA_HD void bsplineBasis(T t, T w[4], T dw[4]) {
  T s = T(1) - t;
  w[0] = s * s * s / T(6);
  w[1] = (T(3) * t * t * t - T(6) * t * t + T(4)) / T(6);
  w[2] = (-T(3) * t * t * t + T(3) * t * t + T(3) * t + T(1)) / T(6);
  w[3] = t * t * t / T(6);
  dw[0] = -s * s / T(2);
  dw[1] = (T(3) * t * t - T(4) * t) / T(2);
  dw[2] = (-T(3) * t * t + T(2) * t + T(1)) / T(2);
  dw[3] = t * t / T(2);
}

// The Bernstein basis is cubicBernstein (core/math/cubic_bernstein.h), which the shaders share.

struct PatchSample {
  Vec3d position, dPds, dPdt;
};

// Evaluates a tensor-product patch given its 1-D basis (B-spline or Bernstein) in double: each
// row contracted along s first (value and s-derivative), then the four rows along t, a third of
// the multiplications of summing the 16 points with their product weights. `Acc` holds the
// sums: Vec3d, or on the host a type doing Vec3d's component operations in SIMD lanes
// (core/math/lanes.h), with the same results bit for bit.
template <typename Acc, typename Point, typename Basis>
TESSERA_HD PatchSample evaluateTensorPatch(const Point cv[16], double s, double t, Basis basis) {
  double ws[4], dws[4], wt[4], dwt[4];
  basis(s, ws, dws);
  basis(t, wt, dwt);
  Acc position, dPds, dPdt;
  for (int row = 0; row < 4; ++row) {
    Acc value, slope;
    for (int col = 0; col < 4; ++col) {
      const Acc p(cv[4 * row + col]);
      value += p * ws[col];
      slope += p * dws[col];
    }
    position += value * wt[row];
    dPds += slope * wt[row];
    dPdt += value * dwt[row];
  }
  return {Vec3d(position), Vec3d(dPds), Vec3d(dPdt)};
}

template <typename Point, typename Acc = Vec3d>
TESSERA_HD PatchSample evaluateBspline(const Point cv[16], double s, double t) {
  return evaluateTensorPatch<Acc>(cv, s, t, [](double x, double* w, double* dw) { bsplineBasis(x, w, dw); });
}

template <typename Point, typename Acc = Vec3d>
TESSERA_HD PatchSample evaluateBezier(const Point cv[16], double s, double t) {
  return evaluateTensorPatch<Acc>(cv, s, t, [](double x, double* w, double* dw) { cubicBernstein(x, w, dw); });
}

// The scalar type of a point type: Vec3T<T> -> T, plain floating point -> itself.
template <typename Point>
struct ScalarOf {
  using type = decltype(Point{}.x);
};
template <>
struct ScalarOf<float> {
  using type = float;
};
template <>
struct ScalarOf<double> {
  using type = double;
};

// One row of M = (1/6)[[1,4,1,0],[0,4,2,0],[0,2,4,0],[0,1,4,1]] applied to four B-spline points.
// Written with symmetric pairs ((a+c) + 4b) so that a shared patch boundary converts to
// bit-identical Bézier points from either side (MATH.md §5).
template <typename Point>
TESSERA_HD void bsplineToBezierCurve(const Point b[4], Point out[4]) {
  using T = typename ScalarOf<Point>::type;
  const T sixth = T(1) / T(6), third = T(1) / T(3);
  out[0] = ((b[0] + b[2]) + b[1] * T(4)) * sixth;
  out[1] = (b[1] * T(2) + b[2]) * third;
  out[2] = (b[1] + b[2] * T(2)) * third;
  out[3] = ((b[1] + b[3]) + b[2] * T(4)) * sixth;
}

template <typename Point>
TESSERA_HD void bsplineToBezier(const Point b[16], Point out[16]) {
  Point rows[16];
  for (int row = 0; row < 4; ++row) bsplineToBezierCurve(b + 4 * row, rows + 4 * row);
  for (int col = 0; col < 4; ++col) {
    Point column[4] = {rows[col], rows[4 + col], rows[8 + col], rows[12 + col]};
    Point converted[4];
    bsplineToBezierCurve(column, converted);
    for (int row = 0; row < 4; ++row) out[4 * row + col] = converted[row];
  }
}

}  // namespace tessera
