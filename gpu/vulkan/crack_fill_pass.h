// The crack-filling post-pass (paper §6.2.4; shaders/crack_fill.comp): reads the raster
// targets, writes the filled colour, patch id and depth images of RenderTargets.
#pragma once

#include <vulkan/vulkan.h>

#include "gpu/vulkan/render_targets.h"

namespace tessera::gpu {

class VulkanContext;

class CrackFillPass {
 public:
  explicit CrackFillPass(const VulkanContext& context);
  ~CrackFillPass();
  CrackFillPass(const CrackFillPass&) = delete;
  CrackFillPass& operator=(const CrackFillPass&) = delete;

  // Points the descriptors at `targets` (when they were re-created).
  void bind(const RenderTargets& targets);
  // Targets must be in the layouts RenderTargets::toCrackFill leaves them in. One dispatch per
  // row band (RenderTargets::bands(kCrackFillBandPixels)), each after the first in a stage of its
  // own (`clock`).
  void record(VkCommandBuffer cmd, const RenderTargets& targets, StageClock& clock) const;

 private:
  VkDevice device_;
  VkSampler sampler_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

}  // namespace tessera::gpu
