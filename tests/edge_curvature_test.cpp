// docs/ADAPTIVE.md §2a against a second code path: bicubics evaluated here from the monomial
// form of the Bernstein polynomials and their exact derivatives, on random nets.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/bounds/edge_curvature.h"

namespace tessera {
namespace {

// Bernstein polynomial k of degree 3 as monomial coefficients, and its d-th derivative at t.
double bernstein(int k, int d, double t) {
  static constexpr double kCoefficients[4][4] = {{1, -3, 3, -1}, {0, 3, -6, 3}, {0, 0, 3, -3}, {0, 0, 0, 1}};
  double value = 0;
  for (int power = d; power < 4; ++power) {
    double factor = 1;
    for (int m = 0; m < d; ++m) factor *= power - m;
    value += kCoefficients[k][power] * factor * std::pow(t, power - d);
  }
  return value;
}

// ∂^(du + dv) f / ∂u^du ∂v^dv of the bicubic with this net (col along u).
Vec3d derivative(const BezierNet& net, int du, int dv, double u, double v) {
  Vec3d sum;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) sum += net[4 * j + i] * (bernstein(i, du, u) * bernstein(j, dv, v));
  }
  return sum;
}

// Half the time an exact quadratic sheet (u, v, αu² + βuv + γv²), where the bound is nearly
// tight; else a gently curved sheet with noise (second derivatives of mixed signs and directions).
BezierNet randomNet(std::mt19937& rng) {
  std::uniform_real_distribution<double> coordinate(-1, 1);
  BezierNet net;
  if (rng() % 2 == 0) {
    static constexpr double kSquare[4] = {0, 0, 1 / 3.0, 1};  // u² in Bernstein form
    const double alpha = coordinate(rng), beta = coordinate(rng), gamma = coordinate(rng);
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) {
        net[4 * j + i] = Vec3d(i / 3.0, j / 3.0, alpha * kSquare[i] + beta * i * j / 9.0 + gamma * kSquare[j]);
      }
    }
    return net;
  }
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      net[4 * j + i] = Vec3d(i / 3.0, j / 3.0, 0) + Vec3d(coordinate(rng), coordinate(rng), coordinate(rng)) * 0.3;
    }
  }
  return net;
}

TEST(EdgeCurvature, SimplexMaxIsTheMaximumOverTheSimplex) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> weight(0, 1);
  for (int trial = 0; trial < 300; ++trial) {
    double a = weight(rng), b = weight(rng), c = weight(rng);
    if (trial % 5 == 0) a = 0;  // degenerate: one edge without weight
    if (trial % 7 == 0) b = c;   // the zip's shape: two equal rungs
    constexpr int kSteps = 400;
    double best = 0;
    for (int i = 0; i <= kSteps; ++i) {
      for (int j = 0; i + j <= kSteps; ++j) {
        const double l0 = double(i) / kSteps, l1 = double(j) / kSteps, l2 = 1 - l0 - l1;
        best = std::max(best, a * l0 * l1 + b * l1 * l2 + c * l0 * l2);
      }
    }
    const double exact = simplexMax(a, b, c);
    EXPECT_GE(exact, best - 1e-12) << a << " " << b << " " << c;
    EXPECT_LE(exact, best + 1e-4) << a << " " << b << " " << c;
  }
}

// Every combination p f_uu + q f_uv + r f_vv, and every third derivative, sampled on the square,
// stays within what the net's data bound.
TEST(EdgeCurvature, BoundsHoldEverywhereOnTheSquare) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> factor(-2, 2);
  for (int trial = 0; trial < 40; ++trial) {
    const BezierNet net = randomNet(rng);
    const EdgeCurvature e = edgeCurvature(net);
    const double p = factor(rng), q = factor(rng), r = factor(rng);
    const double bound = combinationBound(e, p, q, r);
    double sampled = 0, third[4] = {0, 0, 0, 0};
    for (int j = 0; j <= 16; ++j) {
      for (int i = 0; i <= 16; ++i) {
        const double u = i / 16.0, v = j / 16.0;
        const Vec3d value = derivative(net, 2, 0, u, v) * p + derivative(net, 1, 1, u, v) * q + derivative(net, 0, 2, u, v) * r;
        sampled = std::max(sampled, length(value));
        for (int k = 0; k < 4; ++k) third[k] = std::max(third[k], length(derivative(net, 3 - k, k, u, v)));
      }
    }
    EXPECT_LE(sampled, bound * (1 + 1e-9) + 1e-12);
    // Never above the sum of the norms (what §2's form adds).
    EXPECT_LE(bound, (std::abs(p) * std::sqrt(e.uu) + std::abs(q) * std::sqrt(e.uv) + std::abs(r) * std::sqrt(e.vv)) * (1 + 1e-6));
    for (int k = 0; k < 4; ++k) EXPECT_LE(third[k], e.third[k] * (1 + 1e-6) + 1e-12) << "third derivative " << k;
  }
}

// The claim itself: every triangle a grid tile can make (cell halves along either diagonal, and
// zip triangles with one edge of at most a cell along a side and two rungs reaching one row
// across within a cell's width) is within gridTileBound of the bicubic at equal parameters.
TEST(EdgeCurvature, GridTileBoundHoldsForEveryTriangleAGridTileMakes) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> unit(0, 1);
  int checked = 0;
  double tightest = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const BezierNet net = randomNet(rng);
    const EdgeCurvature e = edgeCurvature(net);
    const int ru = 2 + trial % 5, rv = 2 + (trial / 5) % 4;
    const double w = 1.0 / ru, h = 1.0 / rv, bound = gridTileBound(e, ru, rv);
    double worst = 0;
    auto check = [&](const double (&x)[3][2]) {
      const Vec3d f[3] = {derivative(net, 0, 0, x[0][0], x[0][1]), derivative(net, 0, 0, x[1][0], x[1][1]),
                          derivative(net, 0, 0, x[2][0], x[2][1])};
      constexpr int kSteps = 12;
      for (int i = 0; i <= kSteps; ++i) {
        for (int j = 0; i + j <= kSteps; ++j) {
          const double l0 = double(i) / kSteps, l1 = double(j) / kSteps, l2 = 1 - l0 - l1;
          const double u = l0 * x[0][0] + l1 * x[1][0] + l2 * x[2][0], v = l0 * x[0][1] + l1 * x[1][1] + l2 * x[2][1];
          worst = std::max(worst, length(derivative(net, 0, 0, u, v) - (f[0] * l0 + f[1] * l1 + f[2] * l2)));
        }
      }
      ++checked;
    };
    for (int cj = 0; cj < rv; ++cj) {
      for (int ci = 0; ci < ru; ++ci) {
        const double u0 = ci * w, v0 = cj * h, u1 = u0 + w, v1 = v0 + h;
        check({{u0, v0}, {u1, v0}, {u1, v1}}), check({{u0, v0}, {u1, v1}, {u0, v1}});
        check({{u0, v0}, {u1, v0}, {u0, v1}}), check({{u1, v0}, {u1, v1}, {u0, v1}});
        // Zip triangles along each direction: a side segment inside the cell and a row point
        // within a cell's width of both its ends, one row across.
        const double a = u0 + unit(rng) * w / 2, b = a + unit(rng) * w / 2, r = std::clamp(a + (unit(rng) - 0.5) * w, 0.0, 1.0);
        if (v1 <= 1 && std::abs(r - b) <= w) check({{a, v0}, {b, v0}, {r, v1}});
        // The extreme zip triangle: a short side segment whose two rungs are nearly the cell's diagonal.
        if (u1 + w <= 1 + 1e-12) check({{u1, v0}, {u1 + 1e-3 * w, v0}, {u0, v1}});
        const double c = v0 + unit(rng) * h / 2, d = c + unit(rng) * h / 2, s = std::clamp(c + (unit(rng) - 0.5) * h, 0.0, 1.0);
        if (std::abs(s - d) <= h) check({{u1, c}, {u1, d}, {u0, s}});
      }
    }
    EXPECT_LE(worst, bound) << ru << " x " << rv;
    tightest = std::max(tightest, worst / bound);
  }
  EXPECT_GT(checked, 1000);
  // Not a bound that could not fail: on the quadratic sheets some triangle comes close to it.
  EXPECT_GT(tightest, 0.8);
}

}  // namespace
}  // namespace tessera
