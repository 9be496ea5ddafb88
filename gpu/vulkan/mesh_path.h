// The geometry path for devices with VK_EXT_mesh_shader (paper §6.2.2: tessellation inside
// the mesh shader, nothing stored in between). patches.task culls and launches meshlets,
// patches.mesh evaluates them with the same pattern and evaluation code as the compute path,
// shade.frag (per-primitive variant) shades. Constructed only when the device supports it.
#pragma once

#include <vulkan/vulkan.h>

#include <array>

#include "gpu/vulkan/frame_uniforms.h"
#include "gpu/vulkan/patch_batches.h"
#include "gpu/vulkan/render_targets.h"
#include "gpu/vulkan/stage_clock.h"

namespace tessera::gpu {

class VulkanContext;

class MeshPath {
 public:
  explicit MeshPath(const VulkanContext& context);
  ~MeshPath();
  MeshPath(const MeshPath&) = delete;
  MeshPath& operator=(const MeshPath&) = delete;

  // Batches are bounded only by the number of task workgroups one draw may launch.
  static BatchLimits batchLimits(const VulkanContext& context);

  void prepare(const SharedFrameBuffers& shared);
  void record(VkCommandBuffer cmd, const PatchUpload& upload, const RenderTargets& targets,
              const std::array<float, 4>& background, StageClock& clock) const;

 private:
  VkDevice device_;
  PFN_vkCmdDrawMeshTasksEXT drawMeshTasks_;
  VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

}  // namespace tessera::gpu
