#include "core/depth_bound.h"

#include <algorithm>
#include <cmath>

#include "core/fas_rules.h"
#include "core/innermost_patch.h"
#include "core/ring_patches.h"

namespace tessera {

namespace {

// Dense row-major matrix, just enough for the offline linear model.
struct Matrix {
  int rows = 0, cols = 0;
  std::vector<double> a;
  Matrix(int r, int c) : rows(r), cols(c), a(size_t(r) * c, 0.0) {}
  double& at(int r, int c) { return a[size_t(r) * cols + c]; }
  double at(int r, int c) const { return a[size_t(r) * cols + c]; }
  const double* row(int r) const { return a.data() + size_t(r) * cols; }
};

Matrix multiply(const Matrix& x, const Matrix& y) {
  Matrix z(x.rows, y.cols);
  for (int r = 0; r < x.rows; ++r) {
    double* out = z.a.data() + size_t(r) * z.cols;
    for (int k = 0; k < x.cols; ++k) {
      double w = x.at(r, k);
      if (w == 0.0) continue;
      const double* in = y.row(k);
      for (int c = 0; c < y.cols; ++c) out[c] += w * in[c];
    }
  }
  return z;
}

Matrix identity(int n) {
  Matrix m(n, n);
  for (int i = 0; i < n; ++i) m.at(i, i) = 1.0;
  return m;
}

// Column l of a linear map = the map applied to the unit vector e_l.
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

// 16×16 map from a Bézier patch to its restriction to [s0,s1]×[t0,t1].
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

// Rows bounding the error on one sector, in terms of the ring at the innermost level.
struct SectorRows {
  Matrix tiles{0, 0};      // Bézier coefficients of (true − approximation) on each dyadic tile
  Matrix hullTrue{0, 0};   // ring points at depth `tiles` minus the limit point
  Matrix hullApprox{0, 0}; // approximation's control points on the tail minus the limit point
};

void appendRows(Matrix& to, const Matrix& from) {
  to.a.insert(to.a.end(), from.a.begin(), from.a.end());
  to.rows += from.rows;
  to.cols = from.cols;
}

SectorRows sectorRows(const RingRules& rules, int sector, const Matrix& step, const Matrix& ringStep,
                      int tiles) {
  const int n = rules.shape.ringPointCount(), refined = rules.shape.refinedPointCount();
  Matrix approximation = linearMap(16, n, [&](const double* ring, double* out) {
    innermostBezier<double>(rules, sector, [ring](int index) { return ring[index]; }, out);
  });
  Matrix limit = linearMap(1, n, [&](const double* ring, double* out) {
    out[0] = extraordinaryLimit<double>(rules, [ring](int index) { return ring[index]; });
  });
  SectorRows rows;
  rows.tiles = Matrix(0, n);
  Matrix power = identity(n);  // A^t
  for (int t = 0; t < tiles; ++t) {
    Matrix refinedFromRing = multiply(step, power);  // S A^t
    const double size = std::ldexp(1.0, -(t + 1));
    for (int k = 0; k < kPatchesPerSector; ++k) {
      Matrix net = linearMap(16, refined, [&](const double* points, double* out) {
        for (int r = 0; r < 4; ++r) {
          for (int c = 0; c < 4; ++c) {
            out[4 * r + c] = sectorNetPoint<double>(rules, sector, k, r, c,
                                                     [points](int index) { return points[index]; });
          }
        }
      });
      Matrix exact = multiply(bsplineToBezierMatrix(), multiply(net, refinedFromRing));
      int x0, y0;
      sectorPatchOrigin(k, x0, y0);
      Matrix restricted = multiply(restriction(x0 * size, (x0 + 1) * size, y0 * size, (y0 + 1) * size),
                                   approximation);
      for (size_t i = 0; i < exact.a.size(); ++i) exact.a[i] -= restricted.a[i];
      appendRows(rows.tiles, exact);
    }
    power = multiply(ringStep, power);
  }
  rows.hullTrue = power;  // A^tiles
  const double tail = std::ldexp(1.0, -tiles);
  rows.hullApprox = multiply(restriction(0, tail, 0, tail), approximation);
  for (Matrix* m : {&rows.hullTrue, &rows.hullApprox}) {
    for (int r = 0; r < m->rows; ++r) {
      for (int c = 0; c < n; ++c) m->at(r, c) -= limit.at(0, c);
    }
  }
  return rows;
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

// Interior rings look the same from every sector; other kinds need every sector.
bool rotationallySymmetric(const RingKind& kind) {
  if (kind.shape.open) return false;
  for (uint8_t s : kind.sharpSpokes) {
    if (s) return false;
  }
  return true;
}

}  // namespace

std::vector<double> computeDepthBound(const RingKind& kind, int maxDepth, int tiles) {
  std::vector<uint8_t> sharp = kind.sharpSpokes;
  sharp.resize(kind.shape.spokeCount(), 0);
  const RingRules rules = makeRingRules(kind.shape, sharp.data(), kind.cornerEv);
  const int n = kind.shape.ringPointCount(), refinedCount = kind.shape.refinedPointCount();
  Matrix step = linearMap(refinedCount, n, [&](const double* in, double* out) {
    refineRingStep<1, double>(rules, in, out);
  });
  Matrix ringStep(n, n);
  std::copy(step.a.begin(), step.a.begin() + size_t(n) * n, ringStep.a.begin());

  Matrix tileRows(0, n), hullTrue(0, n), hullApprox(0, n);
  int sectors = rotationallySymmetric(kind) ? 1 : kind.shape.sectors;
  for (int s = 0; s < sectors; ++s) {
    SectorRows rows = sectorRows(rules, s, step, ringStep, tiles);
    appendRows(tileRows, rows.tiles);
    appendRows(hullTrue, rows.hullTrue);
    appendRows(hullApprox, rows.hullApprox);
  }
  std::vector<double> bound;
  for (int m = 0; m <= maxDepth; ++m) {
    double tail = maxRowNorm(hullTrue) + maxRowNorm(hullApprox);
    // ×(1 + 1e-6): headroom for the rounding of the double-precision model itself.
    bound.push_back(std::max(maxRowNorm(tileRows), tail) * (1.0 + 1e-6));
    if (m == maxDepth) break;
    tileRows = multiply(tileRows, ringStep);
    hullTrue = multiply(hullTrue, ringStep);
    hullApprox = multiply(hullApprox, ringStep);
  }
  return bound;
}

}  // namespace tessera
