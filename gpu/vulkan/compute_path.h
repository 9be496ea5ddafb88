// The geometry path that runs everywhere (lavapipe included): per batch, tessellate.comp
// evaluates each patch into vertex and index buffers and writes one indirect draw per patch
// (empty when culled), then a plain graphics pipeline pulls those vertices (pulled.vert) and
// shades them (shade.frag). Same pattern and shading code as the mesh path.
#pragma once

#include <vulkan/vulkan.h>

#include <array>

#include "gpu/vulkan/frame_uniforms.h"
#include "gpu/vulkan/gpu_memory.h"
#include "gpu/vulkan/patch_batches.h"
#include "gpu/vulkan/render_targets.h"
#include "gpu/vulkan/stage_clock.h"

namespace tessera::gpu {

class VulkanContext;

class ComputePath {
 public:
  explicit ComputePath(const VulkanContext& context);
  ~ComputePath();
  ComputePath(const ComputePath&) = delete;
  ComputePath& operator=(const ComputePath&) = delete;

  // How much one batch may hold: the vertex and index buffers stay within the device's
  // storage-buffer range and a fixed memory budget.
  static BatchLimits batchLimits(const VulkanContext& context);
  static constexpr VkDeviceSize kVertexBytes = 32;    // PulledVertex: vec4 position+id, vec4 normal
  static constexpr VkDeviceSize kTriangleBytes = 12;  // three uint indices

  // Grows the geometry buffers for the largest batch and points the descriptors at them and
  // at this frame's shared buffers. The previous frame must be complete.
  void prepare(const SharedFrameBuffers& shared, const PatchUpload& upload);

  // Records all batches; the first clears the targets (which must be in attachment layouts).
  // Tessellates every batch without culling and copies its vertices and indices into the
  // readback buffers at the batch's place in the whole mesh (Renderer::tessellate).
  void recordReadback(VkCommandBuffer cmd, const PatchUpload& upload, const GpuBuffer& vertices,
                      const GpuBuffer& indices) const;

  void record(VkCommandBuffer cmd, const PatchUpload& upload, const RenderTargets& targets,
              const std::array<float, 4>& background, StageClock& clock) const;

  // The geometry buffers, which grow with the largest batch drawn (up to 512 MiB each): what
  // they hold, and freeing them (the next prepare() makes them again).
  VkDeviceSize geometryBytes() const;
  void releaseGeometry();

 private:
  const VulkanContext& context_;
  VkDevice device_;
  VkDescriptorSetLayout tessellateSetLayout_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout rasterSetLayout_ = VK_NULL_HANDLE;
  VkPipelineLayout tessellateLayout_ = VK_NULL_HANDLE;
  VkPipelineLayout rasterLayout_ = VK_NULL_HANDLE;
  VkPipeline tessellatePipeline_ = VK_NULL_HANDLE;
  VkPipeline rasterPipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet tessellateSet_ = VK_NULL_HANDLE;
  VkDescriptorSet rasterSet_ = VK_NULL_HANDLE;
  GpuBuffer vertices_;
  GpuBuffer indices_;
  GpuBuffer draws_;

  void recordTessellation(VkCommandBuffer cmd, const GeometryBatch& batch, bool cull) const;
};

}  // namespace tessera::gpu
