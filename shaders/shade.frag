#version 460
// Blinn-Phong shading plus the two extra targets the crack filler reads: patch id (R32_UINT)
// and the covering triangle's depth range (RG32F). Compiled twice: for the compute path and,
// with TESSERA_MESH_PATH, for the mesh path, whose flat inputs are per-primitive.
#extension GL_GOOGLE_include_directive : require
#ifdef TESSERA_MESH_PATH
#extension GL_EXT_mesh_shader : require
#define PER_PRIMITIVE perprimitiveEXT
#else
#define PER_PRIMITIVE
#endif

#define FRAME_UNIFORMS_BINDING 2
#include "include/blinn_phong.glsl"
#include "include/frame_uniforms.glsl"

layout(location = 0) in vec3 inWorldPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) flat PER_PRIMITIVE in uint inPatchId;
layout(location = 3) flat PER_PRIMITIVE in vec2 inDepthRange;

layout(location = 0) out vec4 outColor;
layout(location = 1) out uint outPatchId;
layout(location = 2) out vec2 outDepthRange;

void main() {
  vec3 toEye = normalize(frame.eye.xyz - inWorldPosition);
  vec3 toLight = frame.lightDirection.w > 0.5 ? toEye : normalize(frame.lightDirection.xyz);
  vec3 n = normalize(inNormal);
  vec3 rgb = blinnPhong(n, toEye, toLight, frame.lightColor.rgb, frame.ambientColor.rgb,
                        frame.diffuseColor.rgb, frame.specularColor.rgb, frame.specularColor.w);
  outColor = vec4(clamp(rgb, 0.0, 1.0), 1.0);
  outPatchId = inPatchId;
  outDepthRange = inDepthRange;
}
