#version 460
// Image-space crack filling (paper §6.2.4, after [XLC*23]), one invocation per pixel.
// Case 1, dropout: a background pixel most of whose 8 neighbours are covered (isolated by
// patch id) takes the colour, id and depth of the covered neighbour nearest the camera.
// Case 2, a covered pixel showing geometry through a crack: re-filled only if it is isolated
// by patch id AND at least kMinOccluders neighbours' triangles lie entirely in front of its
// own triangle (neighbour's max depth < this pixel's min depth); it takes the nearest of those.
// The isolation test alone misfires on tiny patches; the occlusion test keeps them shaded.
// Reads the raster targets and writes separate images, so neighbours never see a half-done
// result.

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D colorIn;
layout(set = 0, binding = 1) uniform usampler2D patchIdIn;
layout(set = 0, binding = 2) uniform sampler2D depthIn;
layout(set = 0, binding = 3) uniform sampler2D depthRangeIn;
layout(set = 0, binding = 4, rgba8) uniform writeonly image2D colorOut;
layout(set = 0, binding = 5, r32ui) uniform writeonly uimage2D patchIdOut;
layout(set = 0, binding = 6, r32f) uniform writeonly image2D depthOut;

layout(push_constant) uniform Params {
  ivec2 size;
} params;

const uint kBackground = 0xFFFFFFFFu;
const int kMinIsolation = 5;  // "most" of the 8 neighbours differ
const int kMinOccluders = 3;

uint patchIdAt(ivec2 p) {
  if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, params.size))) return kBackground;
  return texelFetch(patchIdIn, p, 0).r;
}

void writeFrom(ivec2 dst, ivec2 src) {
  imageStore(colorOut, dst, texelFetch(colorIn, src, 0));
  imageStore(patchIdOut, dst, uvec4(texelFetch(patchIdIn, src, 0).r));
  imageStore(depthOut, dst, vec4(texelFetch(depthIn, src, 0).r));
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, params.size))) return;
  uint id = patchIdAt(p);
  bool covered = id != kBackground;
  vec2 range = covered ? texelFetch(depthRangeIn, p, 0).rg : vec2(0.0);

  int differing = 0;
  int occluders = 0;
  ivec2 source = p;
  float sourceDepth = 2.0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      if (dx == 0 && dy == 0) continue;
      ivec2 q = p + ivec2(dx, dy);
      uint qid = patchIdAt(q);
      if (qid == id) continue;
      ++differing;
      if (qid == kBackground) continue;
      bool candidate = !covered;
      if (covered) {
        candidate = texelFetch(depthRangeIn, q, 0).g < range.r;
        if (candidate) ++occluders;
      }
      float qDepth = texelFetch(depthIn, q, 0).r;
      if (candidate && qDepth < sourceDepth) {
        sourceDepth = qDepth;
        source = q;
      }
    }
  }
  bool isolated = differing >= kMinIsolation;
  bool crack = isolated && source != p && (!covered || occluders >= kMinOccluders);
  writeFrom(p, crack ? source : p);
}
