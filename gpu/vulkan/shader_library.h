// The SPIR-V compiled from shaders/ at build time (glslc, embedded by cmake/embed_spirv.cmake),
// and shader-module creation.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>

namespace tessera::gpu {

enum class ShaderId {
  kTessellateComp,  // compute path: patch → vertex + index buffers
  kPulledVert,      // compute path: vertex pulling
  kShadeFrag,       // Blinn-Phong + patch id + depth range (compute path)
  kShadeMeshFrag,   // the same with per-primitive inputs (mesh path)
  kPatchesTask,     // mesh path: culling, meshlet launch
  kPatchesMesh,     // mesh path: meshlet tessellation
  kCrackFillComp,   // crack-filling post-pass
};

std::span<const uint32_t> shaderCode(ShaderId id);

// A module the caller destroys (pipelines keep no reference to it after creation).
VkShaderModule createShaderModule(VkDevice device, ShaderId id);

}  // namespace tessera::gpu
