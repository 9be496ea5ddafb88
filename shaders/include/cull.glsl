// Conservative frustum culling of a whole patch: the surface lies in the convex hull of its
// control points, and each clip plane is a linear function of homogeneous clip coordinates,
// so if all 16 points are strictly outside one plane, so is the whole patch.
// A 1% guard band in x and y keeps rounding in the transform from culling a patch that only
// touches the frustum border.
#ifndef TESSERA_CULL_GLSL
#define TESSERA_CULL_GLSL

#extension GL_EXT_control_flow_attributes : require

const float kCullGuardBand = 1.01;

bool patchOutsideFrustum(mat4 viewProj, in vec3 cp[16]) {
  uint outsideAll = 0x3Fu;
  [[unroll]] for (int k = 0; k < 16; ++k) {
    vec4 c = viewProj * vec4(cp[k], 1.0);
    float w = c.w * kCullGuardBand;
    uint m = 0u;
    if (c.x < -w) m |= 1u;
    if (c.x > w) m |= 2u;
    if (c.y < -w) m |= 4u;
    if (c.y > w) m |= 8u;
    if (c.z < -1e-6 * abs(c.w)) m |= 16u;  // behind the near plane ([0,1] depth)
    if (c.z > c.w * (1.0 + 1e-6)) m |= 32u;
    outsideAll &= m;
  }
  return outsideAll != 0u;
}

#endif
