// How many vertices and triangles one patch's tessellation pattern has (tess_pattern.glsl), for
// edge levels e0..e3 (edges v=0, u=1, v=1, u=0; each >= 1). Written once in the subset that GLSL
// and C++ share, so that the shaders (through tess_pattern.glsl) and the renderer's batching
// (gpu/vulkan/patch_batches.cpp) count alike: the boundary carries Σ e_k points and the inner
// grid (Nu-1)(Nv-1), Nu = max(e0, e2), Nv = max(e1, e3); the four trapezoid strips take
// e_k + N - 2 triangles each and the inner quads 2 (Nu-2)(Nv-2), unless the pattern is one strip.
#ifndef TESSERA_TESS_PATTERN_COUNTS_H
#define TESSERA_TESS_PATTERN_COUNTS_H

#ifdef __cplusplus
#define TESSERA_PATTERN_FN inline
#else
#define TESSERA_PATTERN_FN
#endif

TESSERA_PATTERN_FN int tessPatternVertices(int e0, int e1, int e2, int e3) {
  int nu = e0 > e2 ? e0 : e2;
  int nv = e1 > e3 ? e1 : e3;
  return e0 + e1 + e2 + e3 + (nu - 1) * (nv - 1);
}

TESSERA_PATTERN_FN int tessPatternTriangles(int e0, int e1, int e2, int e3) {
  int nu = e0 > e2 ? e0 : e2;
  int nv = e1 > e3 ? e1 : e3;
  if (nu == 1) return e1 + e3;
  if (nv == 1) return e0 + e2;
  int strips = e0 + e1 + e2 + e3 + 2 * (nu - 2) + 2 * (nv - 2);
  return strips + 2 * (nu - 2) * (nv - 2);
}

#endif
