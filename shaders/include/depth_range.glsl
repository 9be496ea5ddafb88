// Window-space depth range of one triangle, for the crack filler's occlusion criterion
// (paper §6.2.4). Depth z/w is affine across a triangle in screen space, so its range is the
// range over the three corners. A triangle reaching behind the eye gets the widest range
// (0, 1): nothing then counts as entirely in front of it, nor it in front of anything.
#ifndef TESSERA_DEPTH_RANGE_GLSL
#define TESSERA_DEPTH_RANGE_GLSL

vec2 triangleDepthRange(vec4 c0, vec4 c1, vec4 c2) {
  if (c0.w <= 0.0 || c1.w <= 0.0 || c2.w <= 0.0) return vec2(0.0, 1.0);
  float z0 = c0.z / c0.w;
  float z1 = c1.z / c1.w;
  float z2 = c2.z / c2.w;
  return vec2(min(z0, min(z1, z2)), max(z0, max(z1, z2)));
}

#endif
