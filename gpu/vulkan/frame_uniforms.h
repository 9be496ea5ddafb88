// Per-frame constants as the shaders read them (shaders/include/frame_uniforms.glsl, std140),
// the per-frame GPU counters, and the buffers both geometry paths share.
#pragma once

#include <cstdint>

#include "gpu/vulkan/camera_math.h"
#include "gpu/vulkan/gpu_memory.h"
#include "gpu/vulkan/render_types.h"

namespace tessera::gpu {

struct FrameUniforms {
  float viewProj[16];
  float eye[4];
  float lightDirection[4];  // w = 1: headlight
  float lightColor[4];
  float ambientColor[4];
  float diffuseColor[4];
  float specularColor[4];  // w: shininess
};
static_assert(sizeof(FrameUniforms) == 160, "std140 layout of FrameUniforms");

FrameUniforms makeFrameUniforms(const Camera& camera, const ViewProjection& vp,
                                const RenderOptions& options);

// Written by the tessellation stage with atomics (culled patches, generated triangles).
struct FrameStats {
  uint32_t culledPatches;
  uint32_t triangles;
};

// Buffers both geometry paths bind; the renderer grows and fills them each frame.
struct SharedFrameBuffers {
  GpuBuffer patches;   // GpuPatch records of the whole frame
  GpuBuffer uniforms;  // FrameUniforms
  GpuBuffer stats;     // FrameStats
};

}  // namespace tessera::gpu
