#version 460
// Compute path, stage 2: non-indexed draw of 3 vertices per triangle that pulls its corners
// from the buffers tessellate.comp wrote. Each invocation transforms all three corners of its
// triangle so it can pass on the triangle's depth range (flat) for crack filling; its own
// position is one of those three, so shared vertices transform to the same bits everywhere.
#extension GL_GOOGLE_include_directive : require

#define FRAME_UNIFORMS_BINDING 2
#include "include/depth_range.glsl"
#include "include/frame_uniforms.glsl"

struct PulledVertex {
  vec4 positionAndId;
  vec4 normal;
};

layout(std430, set = 0, binding = 0) readonly buffer Vertices { PulledVertex vertices[]; };
layout(std430, set = 0, binding = 1) readonly buffer Indices { uint indices[]; };

layout(location = 0) out vec3 outWorldPosition;
layout(location = 1) out vec3 outNormal;
layout(location = 2) flat out uint outPatchId;
layout(location = 3) flat out vec2 outDepthRange;

void main() {
  uint triangle = uint(gl_VertexIndex) / 3u;
  uint corner = uint(gl_VertexIndex) % 3u;
  vec4 clip[3];
  for (uint c = 0u; c < 3u; ++c) {
    vec3 p = vertices[indices[3u * triangle + c]].positionAndId.xyz;
    clip[c] = frame.viewProj * vec4(p, 1.0);
  }
  PulledVertex v = vertices[indices[3u * triangle + corner]];
  gl_Position = clip[corner];
  outWorldPosition = v.positionAndId.xyz;
  outNormal = v.normal.xyz;
  outPatchId = floatBitsToUint(v.positionAndId.w);
  outDepthRange = triangleDepthRange(clip[0], clip[1], clip[2]);
}
