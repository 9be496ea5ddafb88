// Per-frame constants (FrameUniforms in gpu/vulkan/frame_uniforms.h; std140).
// The including shader defines FRAME_UNIFORMS_BINDING first.
#ifndef TESSERA_FRAME_UNIFORMS_GLSL
#define TESSERA_FRAME_UNIFORMS_GLSL

layout(std140, set = 0, binding = FRAME_UNIFORMS_BINDING) uniform FrameUniforms {
  mat4 viewProj;
  vec4 eye;             // xyz: camera position
  vec4 lightDirection;  // xyz: towards the light (world); w = 1: headlight (light at the eye)
  vec4 lightColor;
  vec4 ambientColor;
  vec4 diffuseColor;
  vec4 specularColor;   // w: shininess
} frame;

#endif
