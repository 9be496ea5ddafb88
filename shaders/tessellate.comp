#version 460
// Compute path, stage 1 (paper Fig. 8 "TES"): one workgroup evaluates one patch into the
// batch's vertex and index buffers and writes that patch's indirect draw (zero vertices when
// frustum-culled). The raster stage then pulls the vertices (pulled.vert).
#extension GL_GOOGLE_include_directive : require

#define FRAME_UNIFORMS_BINDING 5
#include "include/cull.glsl"
#include "include/frame_uniforms.glsl"
#include "include/patch_data.glsl"
#include "include/patch_vertex.glsl"

layout(local_size_x = 64) in;

layout(push_constant) uniform Batch {
  uint firstPatch;
  uint patchCount;
  uint cullPatches;  // 0 when tessellating for readback (Renderer::tessellate): keep everything
} batch;

struct PulledVertex {
  vec4 positionAndId;  // w: patch id bits
  vec4 normal;
};

struct DrawCommand {
  uint vertexCount;
  uint instanceCount;
  uint firstVertex;
  uint firstInstance;
};

layout(std430, set = 0, binding = 0) readonly buffer Patches { GpuPatch patches[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Vertices { PulledVertex vertices[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Indices { uint indices[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Draws { DrawCommand draws[]; };
layout(std430, set = 0, binding = 4) buffer Stats {
  uint culledPatches;
  uint triangles;
} stats;

void main() {
  uint slot = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  if (slot >= batch.patchCount) return;
  uint patchIndex = batch.firstPatch + slot;
  vec3 cp[16];
  LOAD_CONTROL_POINTS(patches, patchIndex, cp);
  uvec4 info = patches[patchIndex].info;
  bool culled = batch.cullPatches != 0u && patchOutsideFrustum(frame.viewProj, cp);
  TessLevels L = makeTessLevels(patches[patchIndex].levels);
  uint triangleCount = uint(patternTriangleCount(L));
  uint firstVertex = info.y;
  uint firstTriangle = info.z;
  if (gl_LocalInvocationIndex == 0u) {
    draws[slot] = DrawCommand(culled ? 0u : 3u * triangleCount, 1u, 3u * firstTriangle, 0u);
    if (culled) atomicAdd(stats.culledPatches, 1u);
    else atomicAdd(stats.triangles, triangleCount);
  }
  if (culled) return;

  int vertexCount = patternVertexCount(L);
  for (int v = int(gl_LocalInvocationIndex); v < vertexCount; v += 64) {
    vec3 pos, normal;
    evalPatternVertex(cp, L, v, pos, normal);
    vertices[firstVertex + uint(v)] =
        PulledVertex(vec4(pos, uintBitsToFloat(info.x)), vec4(normal, 0.0));
  }
  for (int t = int(gl_LocalInvocationIndex); t < int(triangleCount); t += 64) {
    uvec3 tri = uvec3(patternTriangle(L, t)) + firstVertex;
    uint base = 3u * (firstTriangle + uint(t));
    indices[base] = tri.x;
    indices[base + 1u] = tri.y;
    indices[base + 2u] = tri.z;
  }
}
