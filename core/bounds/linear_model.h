// The offline linear model of a CER ring (MATH.md §3): linear maps as dense row-major matrices
// (built one unit vector at a time), their products and row norms, the Bézier restriction to a
// sub-rectangle, and the ring's Catmull-Clark step. The depth bounds (core/bounds/depth_bound.h) and the
// benchmarks' control-mesh comparator (bench/tess_depth.h) are computed with it, in double.
#pragma once

#include <cstddef>
#include <vector>

#include "core/rings/fas_rules.h"

namespace tessera {

struct Matrix {
  int rows = 0, cols = 0;
  std::vector<double> a;
  Matrix(int r, int c) : rows(r), cols(c), a(size_t(r) * c, 0.0) {}
  double& at(int r, int c) { return a[size_t(r) * cols + c]; }
  double at(int r, int c) const { return a[size_t(r) * cols + c]; }
  const double* row(int r) const { return a.data() + size_t(r) * cols; }
};

Matrix multiply(const Matrix& x, const Matrix& y);
Matrix identity(int n);
// `from`'s rows below `to`'s.
void appendRows(Matrix& to, const Matrix& from);
// The largest ℓ1 norm of a row: by the convex hull property, the bound a row set gives.
double maxRowNorm(const Matrix& m);

// The matrix of a linear map: column l is the map applied to the unit vector e_l.
template <typename Map>
Matrix linearMap(int outputs, int inputs, Map apply) {
  Matrix m(outputs, inputs);
  std::vector<double> unit(inputs, 0.0), result(outputs);
  for (int l = 0; l < inputs; ++l) {
    unit[l] = 1.0;
    apply(unit.data(), result.data());
    for (int r = 0; r < outputs; ++r) m.at(r, l) = result[r];
    unit[l] = 0.0;
  }
  return m;
}

// 16×16: a bicubic Bézier patch (row-major, s along columns) → its restriction to
// [s0, s1] × [t0, t1].
Matrix restriction(double s0, double s1, double t0, double t1);
// 16×16: B-spline net → Bézier net.
const Matrix& bsplineToBezierMatrix();

// One Catmull-Clark step of a ring as matrices: S (the 12n+1 refined points from the ring), A
// (the next ring: S's first rows) and ℓ (1 × ring: the EV's limit position).
struct RingStepMatrices {
  Matrix step{0, 0}, ringStep{0, 0}, limit{0, 0};
};
RingStepMatrices ringStepMatrices(const RingRules& rules);

}  // namespace tessera
