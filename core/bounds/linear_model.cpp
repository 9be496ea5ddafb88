#include "core/bounds/linear_model.h"

#include <algorithm>
#include <cmath>

#include "core/math/bicubic.h"
#include "core/rings/innermost_patch.h"

namespace tessera {
namespace {

// 1-D Bézier restriction to [s0, s1]: de Casteljau at s1 (keep left), then at s0/s1 (keep right).
void restrictCurve(double s0, double s1, const double in[4], double out[4]) {
  auto split = [](double t, const double p[4], double left[4], double right[4]) {
    double a = p[0] + t * (p[1] - p[0]), b = p[1] + t * (p[2] - p[1]), c = p[2] + t * (p[3] - p[2]);
    double ab = a + t * (b - a), bc = b + t * (c - b), m = ab + t * (bc - ab);
    double l[4] = {p[0], a, ab, m}, r[4] = {m, bc, c, p[3]};
    for (int i = 0; i < 4; ++i) left[i] = l[i], right[i] = r[i];
  };
  double left[4], right[4], unused[4];
  split(s1, in, left, unused);
  split(s1 > 0 ? s0 / s1 : 0.0, left, unused, right);
  for (int i = 0; i < 4; ++i) out[i] = right[i];
}

}  // namespace

Matrix multiply(const Matrix& x, const Matrix& y) {
  // y's nonzeros by row: a ring's Catmull-Clark step reads a few of its points per row, so the
  // depth bound's products (rows × ringStep, 24 times) skip most of a dense product's work. The
  // sums are the dense product's, term for term in the same order, less the terms that are 0.
  std::vector<int> start(size_t(y.rows) + 1, 0), column;
  std::vector<double> value;
  for (int k = 0; k < y.rows; ++k) {
    for (int c = 0; c < y.cols; ++c) {
      if (y.at(k, c) != 0.0) column.push_back(c), value.push_back(y.at(k, c));
    }
    start[k + 1] = int(column.size());
  }
  Matrix z(x.rows, y.cols);
  for (int r = 0; r < x.rows; ++r) {
    double* out = z.a.data() + size_t(r) * z.cols;
    for (int k = 0; k < x.cols; ++k) {
      const double w = x.at(r, k);
      if (w == 0.0) continue;
      for (int i = start[k]; i < start[k + 1]; ++i) out[column[i]] += w * value[i];
    }
  }
  return z;
}

Matrix identity(int n) {
  Matrix m(n, n);
  for (int i = 0; i < n; ++i) m.at(i, i) = 1.0;
  return m;
}

void appendRows(Matrix& to, const Matrix& from) {
  to.a.insert(to.a.end(), from.a.begin(), from.a.end());
  to.rows += from.rows;
  to.cols = from.cols;
}

double maxRowNorm(const Matrix& m) {
  double worst = 0.0;
  for (int r = 0; r < m.rows; ++r) {
    double sum = 0.0;
    for (int c = 0; c < m.cols; ++c) sum += std::fabs(m.at(r, c));
    worst = std::max(worst, sum);
  }
  return worst;
}

Matrix restriction(double s0, double s1, double t0, double t1) {
  return linearMap(16, 16, [&](const double* in, double* out) {
    double rows[16];
    for (int r = 0; r < 4; ++r) restrictCurve(s0, s1, in + 4 * r, rows + 4 * r);
    for (int c = 0; c < 4; ++c) {
      double column[4] = {rows[c], rows[4 + c], rows[8 + c], rows[12 + c]}, restricted[4];
      restrictCurve(t0, t1, column, restricted);
      for (int r = 0; r < 4; ++r) out[4 * r + c] = restricted[r];
    }
  });
}

const Matrix& bsplineToBezierMatrix() {
  static const Matrix m = linearMap(16, 16, [](const double* in, double* out) { bsplineToBezier(in, out); });
  return m;
}

RingStepMatrices ringStepMatrices(const RingRules& rules) {
  const int n = rules.shape.ringPointCount(), refined = rules.shape.refinedPointCount();
  RingStepMatrices m;
  m.step = linearMap(refined, n, [&](const double* in, double* out) { refineRingStep<1, double>(rules, in, out); });
  m.ringStep = Matrix(n, n);
  std::copy(m.step.a.begin(), m.step.a.begin() + size_t(n) * n, m.ringStep.a.begin());
  m.limit = linearMap(1, n, [&](const double* ring, double* out) {
    out[0] = extraordinaryLimit<double>(rules, [ring](int index) { return ring[index]; });
  });
  return m;
}

}  // namespace tessera
