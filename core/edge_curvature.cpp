#include "core/edge_curvature.h"

#include <cmath>

namespace tessera {

namespace {

// Rounded outward to float, so that stored bounds stay bounds.
float up(double x) {
  const float f = float(x);
  return double(f) >= x ? f : std::nextafter(f, INFINITY);
}
float down(double x) {
  const float f = float(x);
  return double(f) <= x ? f : std::nextafter(f, -INFINITY);
}

// A linear (c0, c1) or quadratic (c0, c1, c2) Bézier coefficient sequence raised to cubic.
void raiseLinear(const Vec3d c[2], Vec3d out[4]) {
  out[0] = c[0], out[1] = (c[0] * 2.0 + c[1]) * (1 / 3.0), out[2] = (c[0] + c[1] * 2.0) * (1 / 3.0), out[3] = c[1];
}
void raiseQuadratic(const Vec3d c[3], Vec3d out[4]) {
  out[0] = c[0], out[1] = (c[0] + c[1] * 2.0) * (1 / 3.0), out[2] = (c[1] * 2.0 + c[2]) * (1 / 3.0), out[3] = c[2];
}

// The Bézier coefficients of f_uu (6 Δ²_u b, degree (1, 3)), f_uv (9 Δ_u Δ_v b, (2, 2)) and f_vv
// (6 Δ²_v b, (3, 1)), each raised to (3, 3), indexed [i along u][j along v].
void raisedSecondDerivatives(const BezierNet& net, Vec3d u[4][4], Vec3d w[4][4], Vec3d v[4][4]) {
  auto at = [&net](int i, int j) { return net[4 * j + i]; };
  for (int j = 0; j < 4; ++j) {
    Vec3d c[2], raised[4];
    for (int i = 0; i < 2; ++i) c[i] = (at(i, j) - at(i + 1, j) * 2.0 + at(i + 2, j)) * 6.0;
    raiseLinear(c, raised);
    for (int i = 0; i < 4; ++i) u[i][j] = raised[i];
  }
  for (int i = 0; i < 4; ++i) {
    Vec3d c[2];
    for (int j = 0; j < 2; ++j) c[j] = (at(i, j) - at(i, j + 1) * 2.0 + at(i, j + 2)) * 6.0;
    raiseLinear(c, v[i]);
  }
  Vec3d alongV[3][4];  // raised along v first, then along u
  for (int i = 0; i < 3; ++i) {
    Vec3d c[3];
    for (int j = 0; j < 3; ++j) c[j] = (at(i, j) - at(i + 1, j) - at(i, j + 1) + at(i + 1, j + 1)) * 9.0;
    raiseQuadratic(c, alongV[i]);
  }
  for (int j = 0; j < 4; ++j) {
    const Vec3d c[3] = {alongV[0][j], alongV[1][j], alongV[2][j]};
    Vec3d raised[4];
    raiseQuadratic(c, raised);
    for (int i = 0; i < 4; ++i) w[i][j] = raised[i];
  }
}

// Hull bounds of ‖f_uuu‖ (6 Δ³_u b, degree (0, 3)), ‖f_uuv‖ (18 Δ²_u Δ_v b, (1, 2)), ‖f_uvv‖
// (18 Δ_u Δ²_v b, (2, 1)) and ‖f_vvv‖ (6 Δ³_v b, (3, 0)).
void thirdDerivativeBounds(const BezierNet& net, double third[4]) {
  auto at = [&net](int i, int j) { return net[4 * j + i]; };
  for (int k = 0; k < 4; ++k) third[k] = 0;
  for (int k = 0; k < 4; ++k) {
    third[0] = std::max(third[0], 6 * length(at(3, k) - at(2, k) * 3.0 + at(1, k) * 3.0 - at(0, k)));
    third[3] = std::max(third[3], 6 * length(at(k, 3) - at(k, 2) * 3.0 + at(k, 1) * 3.0 - at(k, 0)));
  }
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 3; ++b) {
      const Vec3d uuLow = at(a, b) - at(a + 1, b) * 2.0 + at(a + 2, b);
      const Vec3d uuHigh = at(a, b + 1) - at(a + 1, b + 1) * 2.0 + at(a + 2, b + 1);
      third[1] = std::max(third[1], 18 * length(uuHigh - uuLow));
      const Vec3d vvLow = at(b, a) - at(b, a + 1) * 2.0 + at(b, a + 2);
      const Vec3d vvHigh = at(b + 1, a) - at(b + 1, a + 1) * 2.0 + at(b + 1, a + 2);
      third[2] = std::max(third[2], 18 * length(vvHigh - vvLow));
    }
  }
}

}  // namespace

EdgeCurvature edgeCurvature(const BezierNet& net) {
  Vec3d u[4][4], w[4][4], v[4][4];
  raisedSecondDerivatives(net, u, w, v);
  double uu = 0, uv = 0, vv = 0, uvMax = -INFINITY, uvMin = INFINITY, uuW = 0, wVv = 0;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      uu = std::max(uu, dot(u[i][j], u[i][j])), uv = std::max(uv, dot(w[i][j], w[i][j]));
      vv = std::max(vv, dot(v[i][j], v[i][j]));
      const double uDotV = dot(u[i][j], v[i][j]);
      uvMax = std::max(uvMax, uDotV), uvMin = std::min(uvMin, uDotV);
      uuW = std::max(uuW, std::abs(dot(u[i][j], w[i][j]))), wVv = std::max(wVv, std::abs(dot(w[i][j], v[i][j])));
    }
  }
  double third[4];
  thirdDerivativeBounds(net, third);
  EdgeCurvature e;
  e.uu = up(uu), e.uv = up(uv), e.vv = up(vv);
  e.uuVvMax = up(uvMax), e.uuVvMin = down(uvMin);
  e.uuUv = up(uuW), e.uvVv = up(wVv);
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
