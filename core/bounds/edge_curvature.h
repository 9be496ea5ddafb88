// The second derivatives of one bicubic piece along the edges that a grid tile's triangles can
// have, bounded from the piece's Bézier net, and the interpolation bound of an ru × rv grid tile
// over the piece that follows (docs/ADAPTIVE.md §2a). Where §2's form adds the norms of f_uu,
// f_uv and f_vv, each at its own worst point, this one bounds the combination along each edge
// direction, so that second derivatives pointing different ways (saddles, uneven
// parameterizations) partly cancel, and a triangle's error is weighted by where in it the
// edges' terms peak (the variance identity).
#pragma once

#include "core/math/bezier_net.h"

namespace tessera {

// Over the piece's unit square, with U_k, W_k, V_k (k = 0..15) the Bézier coefficients of f_uu,
// f_uv, f_vv degree-raised to bicubic (so that the same k is the same basis function in all
// three), all in the piece's own units. Values are rounded outward to float.
struct EdgeCurvature {
  float uu = 0, uv = 0, vv = 0;   // max ‖U_k‖², ‖W_k‖², ‖V_k‖²
  float uuVvMax = 0, uuVvMin = 0;  // max and min of U_k · V_k
  float uuUv = 0, uvVv = 0;        // max |U_k · W_k|, max |W_k · V_k|
  float third[4] = {0, 0, 0, 0};   // sup ‖f_uuu‖, ‖f_uuv‖, ‖f_uvv‖, ‖f_vvv‖ (hull of their nets)
};

// From a bicubic Bézier net on [0,1]² (bezier_net.h's layout, col along u).
EdgeCurvature edgeCurvature(const BezierNet& net);

// sup over the square of ‖p f_uu + q f_uv + r f_vv‖: every coefficient of that bicubic is
// p U_k + q W_k + r V_k, whose squared norm expands into the terms above, each bounded on its own.
double combinationBound(const EdgeCurvature& e, double p, double q, double r);

// max over λ in the 2-simplex of a λ0λ1 + b λ1λ2 + c λ0λ2 for a, b, c ≥ 0.
double simplexMax(double a, double b, double c);

// docs/ADAPTIVE.md §2a: sup ‖f − L‖ over every triangle an ru × rv grid tile (ru, rv ≥ 2) over
// the whole piece makes, with L the linear interpolant of f at the triangle's corners.
double gridTileBound(const EdgeCurvature& e, int ru, int rv);

}  // namespace tessera
