// Bicubic Bézier evaluation shared by the compute and mesh-shader paths.
// Positions on patch edges come from the 1-D boundary curve (evalCurvePrecise) so that two
// patches sharing an edge produce bit-identical vertices (MATH.md §5, steps 2-4).
#ifndef TESSERA_BEZIER_GLSL
#define TESSERA_BEZIER_GLSL

// [[unroll]] keeps control-point indices constant, so the 16 points stay in registers.
#extension GL_EXT_control_flow_attributes : require

#include "core/math/cubic_bernstein.h"

// Cubic Bernstein basis at t and its derivative, as vectors (kept in registers).
void bernstein3(float t, out vec4 b, out vec4 d) {
  float w[4], dw[4];
  cubicBernstein(t, w, dw);
  b = vec4(w[0], w[1], w[2], w[3]);
  d = vec4(dw[0], dw[1], dw[2], dw[3]);
}

// Surface point and partial derivatives; cp is row-major, cp[4*j+i] = b_ij (u = i/3, v = j/3).
void evalBezierPatch(in vec3 cp[16], vec2 uv, out vec3 pos, out vec3 dpdu, out vec3 dpdv) {
  vec4 bu, du, bv, dv;
  bernstein3(uv.x, bu, du);
  bernstein3(uv.y, bv, dv);
  pos = vec3(0.0);
  dpdu = vec3(0.0);
  dpdv = vec3(0.0);
  [[unroll]] for (int j = 0; j < 4; ++j) {
    vec3 row = vec3(0.0);
    vec3 rowDu = vec3(0.0);
    [[unroll]] for (int i = 0; i < 4; ++i) {
      row += bu[i] * cp[4 * j + i];
      rowDu += du[i] * cp[4 * j + i];
    }
    pos += bv[j] * row;
    dpdu += bv[j] * rowDu;
    dpdv += dv[j] * row;
  }
}

// Boundary curve point. `precise` forbids FMA contraction and reassociation, so the same
// inputs give the same bits wherever this is inlined (both neighbours, both paths).
vec3 evalCurvePrecise(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t) {
  precise float s = 1.0 - t;
  precise float b0 = s * s * s;
  precise float b1 = 3.0 * s * s * t;
  precise float b2 = 3.0 * s * t * t;
  precise float b3 = t * t * t;
  precise vec3 r = ((b0 * p0 + b1 * p1) + b2 * p2) + b3 * p3;
  return r;
}

bool lexLess(vec3 a, vec3 b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

// Canonical direction of a boundary curve: the lexicographically smaller of (p0..p3) and
// (p3..p0). Both patches sharing the curve see the same four points, so they agree.
bool curveReversedIsCanonical(vec3 p0, vec3 p1, vec3 p2, vec3 p3) {
  if (p0 != p3) return lexLess(p3, p0);
  if (p1 != p2) return lexLess(p2, p1);
  return false;
}

#endif
