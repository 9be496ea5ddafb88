// Small builders for the descriptor and pipeline objects each pass creates once. They only
// remove repetition; every pass still states its own bindings.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <initializer_list>

#include "gpu/vulkan/shader_library.h"

namespace tessera::gpu {

struct Binding {
  uint32_t binding;
  VkDescriptorType type;
  VkShaderStageFlags stages;
};

VkDescriptorSetLayout createSetLayout(VkDevice device, std::initializer_list<Binding> bindings);

VkPipelineLayout createPipelineLayout(VkDevice device, VkDescriptorSetLayout setLayout,
                                      uint32_t pushConstantBytes, VkShaderStageFlags pushStages);

// A pool holding `sets` sets with `perType` descriptors of each listed type, and one set
// allocated from it.
VkDescriptorPool createPool(VkDevice device, uint32_t sets,
                            std::initializer_list<VkDescriptorType> types, uint32_t perType);
VkDescriptorSet allocateSet(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout);

VkPipeline createComputePipeline(VkDevice device, VkPipelineLayout layout, ShaderId shader,
                                 VkPipelineCreateFlags flags = 0);

// The raster targets' formats, in attachment order, for dynamic rendering.
struct AttachmentFormats {
  VkFormat color[3];  // colour, patch id, depth range
  VkFormat depth;
};

// A graphics pipeline over the render targets: no vertex input, triangle list, no culling
// (patches may be seen from either side), depth test LESS with writes, no blending.
// `stages` are the shader modules for the vertex/task/mesh and fragment stages.
struct ShaderStage {
  VkShaderStageFlagBits stage;
  ShaderId shader;
};
VkPipeline createGraphicsPipeline(VkDevice device, VkPipelineLayout layout,
                                  std::initializer_list<ShaderStage> stages,
                                  const AttachmentFormats& formats);

void writeBufferDescriptor(VkDevice device, VkDescriptorSet set, uint32_t binding,
                           VkDescriptorType type, VkBuffer buffer);
void writeImageDescriptor(VkDevice device, VkDescriptorSet set, uint32_t binding,
                          VkDescriptorType type, VkImageView view, VkImageLayout layout,
                          VkSampler sampler);

}  // namespace tessera::gpu
