#include "core/bounds/edge_curvature.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/math/lanes.h"

namespace tessera {

namespace {

// std::nextafter(f, +∞) without the library call (half of the eleven roundings below need it, for
// every square the planner bounds): the neighbouring bit pattern.
float nextUp(float f) {
  if (std::isnan(f) || f == INFINITY) return f;
  if (f == 0) return std::numeric_limits<float>::denorm_min();
  const uint32_t bits = std::bit_cast<uint32_t>(f);
  return std::bit_cast<float>(f > 0 ? bits + 1 : bits - 1);
}

// Rounded outward to float, so that stored bounds stay bounds.
float up(double x) {
  const float f = float(x);
  return double(f) >= x ? f : nextUp(f);
}
float down(double x) {
  const float f = float(x);
  return double(f) <= x ? f : -nextUp(-f);
}

// The hull terms are computed in four-double lanes (core/math/lanes.h): every lane does the
// operations the scalar formulas below name, in their order, so the results are theirs bit for
// bit (the planner computes this for every square below a leaf a grid may use: ~7 % of a call on
// the creased torus at 1e-3 when it was written on Vec3d).
Lanes lanesMax(Lanes a, Lanes b) { return a > b ? a : b; }
Lanes lanesMin(Lanes a, Lanes b) { return a < b ? a : b; }
double largest(Lanes a) { return std::max(std::max(a[0], a[1]), std::max(a[2], a[3])); }
double smallest(Lanes a) { return std::min(std::min(a[0], a[1]), std::min(a[2], a[3])); }
Lanes squaredLength(const Lanes p[3]) { return p[0] * p[0] + p[1] * p[1] + p[2] * p[2]; }
Lanes dotLanes(const Lanes p[3], const Lanes q[3]) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; }
Lanes absLanes(Lanes a) { return a < 0 ? -a : a; }

// One coordinate of the net by rows (lanes: i along u, for row j along v) and by columns
// (lanes: j, for column i); b(i, j) = net[4 j + i].
struct NetLanes {
  Lanes row[3][4], col[3][4];
  explicit NetLanes(const BezierNet& net) {
    for (int a = 0; a < 3; ++a) {
      for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) row[a][j][i] = col[a][i][j] = net[4 * j + i][a];
      }
    }
  }
};

// The Bézier coefficients of f_uu (6 Δ²_u b, degree (1, 3)), f_uv (9 Δ_u Δ_v b, (2, 2)) and f_vv
// (6 Δ²_v b, (3, 1)), each raised to (3, 3), coordinate a, index i along u, lanes j along v.
// A linear (c0, c1) sequence raises to (c0, (2 c0 + c1)/3, (c0 + 2 c1)/3, c1), a quadratic
// (c0, c1, c2) to (c0, (c0 + 2 c1)/3, (2 c1 + c2)/3, c2).
void raisedSecondDerivatives(const NetLanes& n, Lanes u[3][4], Lanes w[3][4], Lanes v[3][4]) {
  const double third = 1 / 3.0;
  for (int a = 0; a < 3; ++a) {
    const Lanes* col = n.col[a];
    const Lanes* row = n.row[a];
    const Lanes c0 = (col[0] - col[1] * 2.0 + col[2]) * 6.0, c1 = (col[1] - col[2] * 2.0 + col[3]) * 6.0;
    u[a][0] = c0, u[a][1] = (c0 * 2.0 + c1) * third, u[a][2] = (c0 + c1 * 2.0) * third, u[a][3] = c1;
    // Along v per column i (lanes i), then turned to lanes j.
    const Lanes r0 = (row[0] - row[1] * 2.0 + row[2]) * 6.0, r1 = (row[1] - row[2] * 2.0 + row[3]) * 6.0;
    const Lanes r1Raised = (r0 * 2.0 + r1) * third, r2Raised = (r0 + r1 * 2.0) * third;
    for (int i = 0; i < 4; ++i) v[a][i] = Lanes{r0[i], r1Raised[i], r2Raised[i], r1[i]};
    // Raised along v first (per i = 0..2, from its 3 × 3 twists), then along u.
    Lanes alongV[3];
    for (int i = 0; i < 3; ++i) {
      double c[3];
      for (int j = 0; j < 3; ++j) c[j] = (col[i][j] - col[i + 1][j] - col[i][j + 1] + col[i + 1][j + 1]) * 9.0;
      alongV[i] = Lanes{c[0], (c[0] + c[1] * 2.0) * third, (c[1] * 2.0 + c[2]) * third, c[2]};
    }
    w[a][0] = alongV[0], w[a][1] = (alongV[0] + alongV[1] * 2.0) * third;
    w[a][2] = (alongV[1] * 2.0 + alongV[2]) * third, w[a][3] = alongV[2];
  }
}

// Hull bounds of ‖f_uuu‖ (6 Δ³_u b, degree (0, 3)), ‖f_uuv‖ (18 Δ²_u Δ_v b, (1, 2)), ‖f_uvv‖
// (18 Δ_u Δ²_v b, (2, 1)) and ‖f_vvv‖ (6 Δ³_v b, (3, 0)).
void thirdDerivativeBounds(const NetLanes& n, double third[4]) {
  Lanes uuu[3], vvv[3], uu[2][3], vv[2][3];  // Δ³ along u (lanes j), along v (lanes i); Δ² per offset
  for (int a = 0; a < 3; ++a) {
    const Lanes* col = n.col[a];
    const Lanes* row = n.row[a];
    uuu[a] = col[3] - col[2] * 3.0 + col[1] * 3.0 - col[0];
    vvv[a] = row[3] - row[2] * 3.0 + row[1] * 3.0 - row[0];
    for (int o = 0; o < 2; ++o) {
      uu[o][a] = col[o] - col[o + 1] * 2.0 + col[o + 2];  // Δ²_u at i = o, lanes j
      vv[o][a] = row[o] - row[o + 1] * 2.0 + row[o + 2];  // Δ²_v at j = o, lanes i
    }
  }
  third[0] = 6 * std::sqrt(largest(squaredLength(uuu)));
  third[3] = 6 * std::sqrt(largest(squaredLength(vvv)));
  third[1] = third[2] = 0;
  for (int o = 0; o < 2; ++o) {
    for (int b = 0; b < 3; ++b) {
      const Vec3d uuStep(uu[o][0][b + 1] - uu[o][0][b], uu[o][1][b + 1] - uu[o][1][b], uu[o][2][b + 1] - uu[o][2][b]);
      const Vec3d vvStep(vv[o][0][b + 1] - vv[o][0][b], vv[o][1][b + 1] - vv[o][1][b], vv[o][2][b + 1] - vv[o][2][b]);
      third[1] = std::max(third[1], 18 * length(uuStep));
      third[2] = std::max(third[2], 18 * length(vvStep));
    }
  }
}

}  // namespace

EdgeCurvature edgeCurvature(const BezierNet& net) {
  const NetLanes n(net);
  Lanes u[3][4], w[3][4], v[3][4];
  raisedSecondDerivatives(n, u, w, v);
  Lanes uu = {0, 0, 0, 0}, uv = uu, vv = uu, uuW = uu, wVv = uu;
  Lanes uvMax = {-INFINITY, -INFINITY, -INFINITY, -INFINITY}, uvMin = -uvMax;
  for (int i = 0; i < 4; ++i) {
    const Lanes U[3] = {u[0][i], u[1][i], u[2][i]}, W[3] = {w[0][i], w[1][i], w[2][i]}, V[3] = {v[0][i], v[1][i], v[2][i]};
    uu = lanesMax(uu, squaredLength(U)), uv = lanesMax(uv, squaredLength(W)), vv = lanesMax(vv, squaredLength(V));
    const Lanes uDotV = dotLanes(U, V);
    uvMax = lanesMax(uvMax, uDotV), uvMin = lanesMin(uvMin, uDotV);
    uuW = lanesMax(uuW, absLanes(dotLanes(U, W))), wVv = lanesMax(wVv, absLanes(dotLanes(W, V)));
  }
  double third[4];
  thirdDerivativeBounds(n, third);
  EdgeCurvature e;
  e.uu = up(largest(uu)), e.uv = up(largest(uv)), e.vv = up(largest(vv));
  e.uuVvMax = up(largest(uvMax)), e.uuVvMin = down(smallest(uvMin));
  e.uuUv = up(largest(uuW)), e.uvVv = up(largest(wVv));
  for (int k = 0; k < 4; ++k) e.third[k] = up(third[k]);
  return e;
}

double combinationBound(const EdgeCurvature& e, double p, double q, double r) {
  const double squared = p * p * e.uu + q * q * e.uv + r * r * e.vv + 2 * p * r * (p * r >= 0 ? e.uuVvMax : e.uuVvMin) +
                         2 * std::abs(p * q) * e.uuUv + 2 * std::abs(q * r) * e.uvVv;
  return std::sqrt(std::max(0.0, squared));
}

// An edge's maximum, max(a, b, c)/4, or the stationary point inside the simplex, which is
// λ ∝ (b(a + c − b), c(a + b − c), a(b + c − a)) with value abc / Σλ when all three are positive.
double simplexMax(double a, double b, double c) {
  double best = std::max({a, b, c}) / 4;
  const double l0 = b * (a + c - b), l1 = c * (a + b - c), l2 = a * (b + c - a);
  if (l0 > 0 && l1 > 0 && l2 > 0) best = std::max(best, a * b * c / (l0 + l1 + l2));
  return best;
}

// docs/ADAPTIVE.md §2a. With w × h the cell (piece units): a triangle's error is at most
// ½ max_λ Σ λ_j λ_k ‖D²f[e_jk, e_jk]‖ plus a third-derivative remainder. Every triangle has one
// edge along u (at most w) and two rungs (δ, ±h), |δ| ≤ w, or the same with u and v exchanged.
double gridTileBound(const EdgeCurvature& e, int ru, int rv) {
  const double w = 1.0 / ru, h = 1.0 / rv;
  const double alongU = combinationBound(e, w * w, 0, 0), alongV = combinationBound(e, 0, 0, h * h);
  const double diagonal = combinationBound(e, w * w, 2 * w * h, h * h);
  // Rungs (δ, h) for δ ∈ [−w, w]: the quadratic in δ has Bernstein coefficients h² f_vv,
  // h² f_vv ± w h f_uv and w² f_uu ± 2 w h f_uv + h² f_vv; likewise (w, δ) for δ ∈ [−h, h].
  const double rungU = std::max({alongV, combinationBound(e, 0, w * h, h * h), diagonal});
  const double rungV = std::max({alongU, combinationBound(e, w * w, w * h, 0), diagonal});
  const double quadratic = 0.5 * std::max(simplexMax(alongU, rungU, rungU), simplexMax(alongV, rungV, rungV));
  const double remainder =
      (w * w * w * e.third[0] + 3 * w * w * h * e.third[1] + 3 * w * h * h * e.third[2] + h * h * h * e.third[3]) / 48;
  return (quadratic + remainder) * (1 + 1e-9);
}

}  // namespace tessera
