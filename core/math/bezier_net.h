// Operations on bicubic Bézier nets over a square that the adaptive tessellation's proofs use
// (docs/ADAPTIVE.md): bounds of the second derivatives from second differences, de Casteljau
// halving, re-indexing a net into its root's (u, v) orientation, and the least-squares bicubic
// that stands in for four quadrant nets. Nets are row-major 4×4, index 4*row + col, col along
// the first parameter.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "core/base/host_device.h"
#include "core/base/vec3.h"

namespace tessera {

using BezierNet = std::array<Vec3d, 16>;

// Bounds of ‖∂²f/∂u²‖, ‖∂²f/∂u∂v‖, ‖∂²f/∂v²‖ over a region, in the units of the parameter the
// region is measured in (docs/ADAPTIVE.md §2).
struct Curvature {
  double uu = 0, uv = 0, vv = 0;

  Curvature max(const Curvature& o) const {
    return {std::max(uu, o.uu), std::max(uv, o.uv), std::max(vv, o.vv)};
  }
  // The same bounds for a parameter scaled by `factor` (derivatives scale with factor²).
  Curvature scaled(double factor) const { return {uu * factor, uv * factor, vv * factor}; }
  Curvature transposed() const { return {vv, uv, uu}; }
  bool finite() const { return std::isfinite(uu) && std::isfinite(uv) && std::isfinite(vv); }
};

// Linear interpolation error of a triangle whose parameter box is w × h, for a C¹ map whose
// second derivatives are bounded by `m` over that box (docs/ADAPTIVE.md §2, the FMM86 form):
// ‖f − L‖ ≤ (w² M_uu + 2 w h M_uv + h² M_vv) / 8.
inline double interpolationBound(const Curvature& m, double w, double h) {
  return (w * w * m.uu + 2 * w * h * m.uv + h * h * m.vv) / 8;
}

// The second derivatives of a bicubic Bézier on [0,1]² are Bézier forms with coefficients
// 6 Δ²_u b, 9 Δ_u Δ_v b and 6 Δ²_v b; by the convex hull property their largest coefficient
// norms bound them everywhere on the square.
inline Curvature netCurvature(const Vec3d* b) {
  auto at = [b](int row, int col) { return b[4 * row + col]; };
  double uu = 0, vv = 0, uv = 0;  // squared norms
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 2; ++j) {
      uu = std::max(uu, lengthSquared(at(i, j) - at(i, j + 1) * 2.0 + at(i, j + 2)));
      vv = std::max(vv, lengthSquared(at(j, i) - at(j + 1, i) * 2.0 + at(j + 2, i)));
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      uv = std::max(uv, lengthSquared(at(i, j) - at(i, j + 1) - at(i + 1, j) + at(i + 1, j + 1)));
  }
  return {6 * std::sqrt(uu), 9 * std::sqrt(uv), 6 * std::sqrt(vv)};
}

// De Casteljau at t = 1/2 of one cubic: the half toward t = 0 (`upper` false) or t = 1.
inline void halveCurve(const Vec3d* p, int stride, bool upper, Vec3d* out, int outStride) {
  Vec3d a = p[0], b = p[stride], c = p[2 * stride], d = p[3 * stride];
  Vec3d ab = (a + b) * 0.5, bc = (b + c) * 0.5, cd = (c + d) * 0.5;
  Vec3d abc = (ab + bc) * 0.5, bcd = (bc + cd) * 0.5, mid = (abc + bcd) * 0.5;
  const Vec3d lower[4] = {a, ab, abc, mid}, higher[4] = {mid, bcd, cd, d};
  for (int k = 0; k < 4; ++k) out[k * outStride] = upper ? higher[k] : lower[k];
}

// One half of the cubics through a, a + stride, a + 2 stride, a + 3 stride (each `width` doubles
// side by side: several curves at once), halveCurve's sums element by element.
template <int width>
inline void halveCurves(const double* a, int stride, bool upper, double* out, int outStride) {
  for (int e = 0; e < width; ++e) {
    const double p0 = a[e], p1 = a[stride + e], p2 = a[2 * stride + e], p3 = a[3 * stride + e];
    const double ab = (p0 + p1) * 0.5, bc = (p1 + p2) * 0.5, cd = (p2 + p3) * 0.5;
    const double abc = (ab + bc) * 0.5, bcd = (bc + cd) * 0.5, mid = (abc + bcd) * 0.5;
    out[e] = upper ? mid : p0;
    out[outStride + e] = upper ? bcd : ab;
    out[2 * outStride + e] = upper ? cd : abc;
    out[3 * outStride + e] = upper ? p3 : mid;
  }
}

// The net of quadrant (qu, qv) ∈ {0,1}² of the square: u ∈ [qu/2, (qu+1)/2], v likewise. The
// rows halved along u (each row's points, three coordinates at a time), then the four columns at
// once along v (a row of the net is 12 contiguous doubles): halveCurve's sums, bit for bit.
inline BezierNet quadrantNet(const BezierNet& net, int qu, int qv) {
  static_assert(sizeof(BezierNet) == 48 * sizeof(double) && std::is_trivially_copyable_v<BezierNet>);
  double in[48], rows[48], columns[48];
  std::memcpy(in, net.data(), sizeof in);
  for (int row = 0; row < 4; ++row) halveCurves<3>(in + 12 * row, 3, qu == 1, rows + 12 * row, 3);
  halveCurves<12>(rows, 12, qv == 1, columns, 12);
  BezierNet out;
  std::memcpy(out.data(), columns, sizeof columns);
  return out;
}

// All four quadrant nets at once, *out[qu + 2 qv] = quadrantNet(net, qu, qv) bit for bit: each
// row and then each of the seven columns halved once, instead of once per quadrant.
inline void quadrantNets(const BezierNet& net, BezierNet* const out[4]) {
  Vec3d rows[4][7];  // each row's two halves, sharing the middle point
  for (int row = 0; row < 4; ++row) {
    halveCurve(&net[4 * row], 1, false, &rows[row][0], 1);
    halveCurve(&net[4 * row], 1, true, &rows[row][3], 1);
  }
  for (int col = 0; col < 7; ++col) {
    const Vec3d column[4] = {rows[0][col], rows[1][col], rows[2][col], rows[3][col]};
    Vec3d lower[4], upper[4];
    halveCurve(column, 1, false, lower, 1);
    halveCurve(column, 1, true, upper, 1);
    for (int qu = 0; qu < 2; ++qu) {
      const int c = col - 3 * qu;  // the column's place in quadrant column qu
      if (c < 0 || c > 3) continue;
      for (int k = 0; k < 4; ++k) (*out[qu])[4 * k + c] = lower[k], (*out[qu + 2])[4 * k + c] = upper[k];
    }
  }
}

// How a piece's (s, t) frame sits in its root's (u, v): (su, sv) and (tu, tv) are the unit
// directions, (±1, 0) or (0, ±1), of the piece's axes in the root.
struct Orientation {
  int su = 1, sv = 0, tu = 0, tv = 1;

  bool swapsAxes() const { return su == 0; }
  // +1 when (s, t) and (u, v) have the same handedness.
  TESSERA_HD int handedness() const { return su * tv - sv * tu; }
  // Three bits, kept per leaf: axes swapped, s backward, t backward.
  uint8_t code() const {
    const bool swapped = swapsAxes();
    return uint8_t((swapped ? 1 : 0) | ((swapped ? sv : su) < 0 ? 2 : 0) | ((swapped ? tu : tv) < 0 ? 4 : 0));
  }
  TESSERA_HD static Orientation fromCode(uint8_t code) {
    const int s = code & 2 ? -1 : 1, t = code & 4 ? -1 : 1;
    return code & 1 ? Orientation{0, s, t, 0} : Orientation{s, 0, 0, t};
  }
};

// Re-indexes a net given in a piece's (s, t) frame into root order (col along u, row along v).
inline BezierNet orientNet(const Vec3d* piece, const Orientation& o) {
  BezierNet out;
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) {
      // The Greville point (col/3, row/3) of the square in the piece's frame.
      // A backward axis starts at the far side of the square.
      const int s = o.su * col + o.sv * row + (o.su + o.sv < 0 ? 3 : 0);
      const int t = o.tu * col + o.tv * row + (o.tu + o.tv < 0 ? 3 : 0);
      out[4 * row + col] = piece[4 * t + s];
    }
  }
  return out;
}

// Largest ‖a_ij − b_ij‖: by the convex hull property, a bound of ‖A − B‖ over the square for
// the two bicubics with these nets.
inline double netDistance(const BezierNet& a, const BezierNet& b) {
  double d2 = 0;
  for (int k = 0; k < 16; ++k) d2 = std::max(d2, lengthSquared(a[k] - b[k]));
  return std::sqrt(d2);
}

// Corners of a square: 0 = (0,0), 1 = (1,0), 2 = (1,1), 3 = (0,1); their net indices.
inline constexpr int kCornerIndex[4] = {0, 3, 15, 12};
// The net indices along side k (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0), parameter increasing.
inline constexpr int kSideIndex[4][4] = {{0, 1, 2, 3}, {3, 7, 11, 15}, {12, 13, 14, 15}, {0, 4, 8, 12}};

// The bilinear interpolant of four corner values (points or scalars) at (x, y) of their square.
template <class T>
T bilinearAt(const T corners[4], double x, double y) {
  return corners[0] * ((1 - x) * (1 - y)) + corners[1] * (x * (1 - y)) + corners[2] * (x * y) +
         corners[3] * ((1 - x) * y);
}

// The bilinear interpolant of four corner values, as a bicubic net (an affine function of each
// parameter has its Bézier coefficients at the Greville points i/3).
BezierNet bilinearNet(const Vec3d corners[4]);

// Hull bound of ‖A − B‖ over the square, tightened by one de Casteljau split into quadrants
// (exact for quadratic differences).
double splitNetDistance(const BezierNet& a, const BezierNet& b);

// Hull bound of ‖c − chord‖ along side k of a net (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0),
// the chord running between two end values, tightened by one split.
double sideChordDistance(const BezierNet& net, int side, const Vec3d& from, const Vec3d& to);
// The corners side k runs between (from, to).
inline void sideCorners(int side, int& from, int& to) {
  static constexpr int kFrom[4] = {0, 1, 3, 0}, kTo[4] = {1, 2, 2, 3};
  from = kFrom[side], to = kTo[side];
}
// sideChordDistance for every side, each chord between two of the given corner values.
inline std::array<double, 4> chordBows(const BezierNet& net, const Vec3d corners[4]) {
  std::array<double, 4> bows;
  for (int side = 0; side < 4; ++side) {
    int from, to;
    sideCorners(side, from, to);
    bows[side] = sideChordDistance(net, side, corners[from], corners[to]);
  }
  return bows;
}

// The least-squares bicubic g over a square whose quadrant nets best match `quadrants` (in
// quadrant order qv * 2 + qu): minimises Σ_k ‖C_k − S_k g‖² over control points, S_k the
// de Casteljau restriction to quadrant k. Separable: S_k = H_qv ⊗ H_qu, so the normal equations
// are (G ⊗ G) g = Σ (H_qvᵀ ⊗ H_quᵀ) C_k with G = H_0ᵀH_0 + H_1ᵀH_1.
BezierNet coarsenNets(const BezierNet quadrants[4]);

}  // namespace tessera
