// Position and normal of one tessellation vertex (tess_pattern.glsl numbering).
// Corners are the control points themselves; other boundary vertices come from the edge's
// boundary curve evaluated in its canonical direction with `precise` (MATH.md §5), so that
// neighbours agreeing on an edge level produce bit-identical vertices. Normals come from the
// analytic derivatives of this patch (they need not match across edges; positions must).
#ifndef TESSERA_PATCH_VERTEX_GLSL
#define TESSERA_PATCH_VERTEX_GLSL

#include "bezier.glsl"
#include "tess_pattern.glsl"

// Control-point indices of boundary side k in counter-clockwise order.
int boundaryControlIndex(int side, int n) {
  if (side == 0) return n;            // 0 1 2 3
  if (side == 1) return 3 + 4 * n;    // 3 7 11 15
  if (side == 2) return 15 - n;       // 15 14 13 12
  return 12 - 4 * n;                  // 12 8 4 0
}

vec3 boundaryPosition(in vec3 cp[16], TessLevels L, int side, int step) {
  vec3 p0 = cp[boundaryControlIndex(side, 0)];
  if (step == 0) return p0;
  vec3 p1 = cp[boundaryControlIndex(side, 1)];
  vec3 p2 = cp[boundaryControlIndex(side, 2)];
  vec3 p3 = cp[boundaryControlIndex(side, 3)];
  int e = L.e[side];
  if (curveReversedIsCanonical(p0, p1, p2, p3)) {
    return evalCurvePrecise(p3, p2, p1, p0, float(e - step) / float(e));
  }
  return evalCurvePrecise(p0, p1, p2, p3, float(step) / float(e));
}

// Unit normal from the derivatives at uv; where they degenerate (a collapsed edge or corner)
// it is taken a little inside the patch, where the surface is regular again.
vec3 patchNormal(in vec3 cp[16], vec2 uv, vec3 du, vec3 dv) {
  vec3 n = cross(du, dv);
  float scale = max(dot(du, du), dot(dv, dv));
  if (dot(n, n) <= 1e-12 * scale * scale || scale == 0.0) {
    vec3 pos;
    evalBezierPatch(cp, mix(uv, vec2(0.5), 1e-3), pos, du, dv);
    n = cross(du, dv);
  }
  float len = length(n);
  return len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
}

void evalPatternVertex(in vec3 cp[16], TessLevels L, int id, out vec3 pos, out vec3 normal) {
  PatternVertex pv = patternVertex(L, id);
  vec3 du, dv;
  evalBezierPatch(cp, pv.uv, pos, du, dv);
  // On the boundary the position must come from the edge's own curve (see top of file); the
  // surface value there differs from it by rounding only.
  if (pv.side < 4) pos = boundaryPosition(cp, L, pv.side, pv.step);
  normal = patchNormal(cp, pv.uv, du, dv);
}

#endif
