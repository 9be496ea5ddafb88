#include "core/math/bezier_net.h"

namespace tessera {

namespace {

using Matrix4 = std::array<std::array<double, 4>, 4>;

// De Casteljau's halving matrices: the coefficients of the lower and upper half of a cubic.
constexpr Matrix4 kHalf[2] = {
    {{{1, 0, 0, 0}, {0.5, 0.5, 0, 0}, {0.25, 0.5, 0.25, 0}, {0.125, 0.375, 0.375, 0.125}}},
    {{{0.125, 0.375, 0.375, 0.125}, {0, 0.25, 0.5, 0.25}, {0, 0, 0.5, 0.5}, {0, 0, 0, 1}}}};

Matrix4 inverse(Matrix4 a) {
  Matrix4 inv{};
  for (int i = 0; i < 4; ++i) inv[i][i] = 1;
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 4; ++r) {
      if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
    }
    std::swap(a[col], a[pivot]);
    std::swap(inv[col], inv[pivot]);
    const double scale = 1 / a[col][col];
    for (int k = 0; k < 4; ++k) a[col][k] *= scale, inv[col][k] *= scale;
    for (int r = 0; r < 4; ++r) {
      if (r == col) continue;
      const double f = a[r][col];
      for (int k = 0; k < 4; ++k) a[r][k] -= f * a[col][k], inv[r][k] -= f * inv[col][k];
    }
  }
  return inv;
}

// G⁻¹ with G = H_0ᵀH_0 + H_1ᵀH_1.
const Matrix4& gramInverse() {
  static const Matrix4 value = [] {
    Matrix4 g{};
    for (const Matrix4& h : kHalf) {
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
          for (int k = 0; k < 4; ++k) g[i][j] += h[k][i] * h[k][j];
        }
      }
    }
    return inverse(g);
  }();
  return value;
}

}  // namespace

BezierNet bilinearNet(const Vec3d corners[4]) {
  BezierNet out;
  for (int row = 0; row < 4; ++row) {
    const double y = row / 3.0;
    for (int col = 0; col < 4; ++col) {
      const double x = col / 3.0;
      out[4 * row + col] = bilinearAt(corners, x, y);
    }
  }
  return out;
}

namespace {

// A cubic halved at 1/2: both halves' coefficients, the middle one shared (a, ab, abc, mid, bcd,
// cd, d), as halveCurve computes them.
void splitCubic(double a, double b, double c, double d, double out[7]) {
  const double ab = (a + b) * 0.5, bc = (b + c) * 0.5, cd = (c + d) * 0.5;
  const double abc = (ab + bc) * 0.5, bcd = (bc + cd) * 0.5;
  out[0] = a, out[1] = ab, out[2] = abc, out[3] = (abc + bcd) * 0.5, out[4] = bcd, out[5] = cd, out[6] = d;
}

}  // namespace

double splitNetDistance(const BezierNet& a, const BezierNet& b) {
  // De Casteljau at 1/2 in both directions lays the four quadrant nets out on one 7 × 7 grid,
  // one coordinate at a time (the squared lengths summed in x, y, z order, as dot() does).
  double d2[7][7] = {};
  for (int axis = 0; axis < 3; ++axis) {
    double rows[4][7];
    for (int r = 0; r < 4; ++r) {
      splitCubic(a[4 * r][axis] - b[4 * r][axis], a[4 * r + 1][axis] - b[4 * r + 1][axis],
                 a[4 * r + 2][axis] - b[4 * r + 2][axis], a[4 * r + 3][axis] - b[4 * r + 3][axis], rows[r]);
    }
    for (int c = 0; c < 7; ++c) {
      double column[7];
      splitCubic(rows[0][c], rows[1][c], rows[2][c], rows[3][c], column);
      for (int r = 0; r < 7; ++r) d2[r][c] += column[r] * column[r];
    }
  }
  double worst = 0;
  for (const auto& row : d2) {
    for (double value : row) worst = std::max(worst, value);
  }
  return std::sqrt(worst);
}

double sideChordDistance(const BezierNet& net, int side, const Vec3d& from, const Vec3d& to) {
  Vec3d difference[4];
  for (int i = 0; i < 4; ++i) difference[i] = net[kSideIndex[side][i]] - (from * (1 - i / 3.0) + to * (i / 3.0));
  double d2 = 0;
  for (int half = 0; half < 2; ++half) {
    Vec3d part[4];
    halveCurve(difference, 1, half == 1, part, 1);
    for (const Vec3d& p : part) d2 = std::max(d2, lengthSquared(p));
  }
  return std::sqrt(d2);
}

// Nets as matrices N[row][col] (row along v): the quadrant restriction is H_qv N H_quᵀ, so the
// normal equations read G g G = Σ_k H_qvᵀ C_k H_qu and g = G⁻¹ (Σ_k H_qvᵀ C_k H_qu) G⁻¹.
BezierNet coarsenNets(const BezierNet quadrants[4]) {
  BezierNet rhs{};
  for (int k = 0; k < 4; ++k) {
    const Matrix4& hu = kHalf[k % 2];
    const Matrix4& hv = kHalf[k / 2];
    for (int row = 0; row < 4; ++row) {
      for (int col = 0; col < 4; ++col) {
        Vec3d sum;
        for (int r = 0; r < 4; ++r) {
          for (int c = 0; c < 4; ++c) sum += quadrants[k][4 * r + c] * (hv[r][row] * hu[c][col]);
        }
        rhs[4 * row + col] += sum;
      }
    }
  }
  const Matrix4& gi = gramInverse();
  BezierNet out{};
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) {
      Vec3d sum;
      for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) sum += rhs[4 * r + c] * (gi[row][r] * gi[c][col]);
      }
      out[4 * row + col] = sum;
    }
  }
  return out;
}

}  // namespace tessera
