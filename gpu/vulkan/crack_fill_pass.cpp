#include "gpu/vulkan/crack_fill_pass.h"

#include "gpu/vulkan/pipeline_builders.h"
#include "gpu/vulkan/vulkan_context.h"
#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace {

constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
constexpr VkDescriptorType kStorageImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;
constexpr uint32_t kTile = 8;  // local_size of crack_fill.comp

struct Params {
  int32_t width;
  int32_t height;
};

}  // namespace

CrackFillPass::CrackFillPass(const VulkanContext& context) : device_(context.device()) {
  // texelFetch ignores filtering, but a combined sampler is what sampler2D needs.
  VkSamplerCreateInfo sampler{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  sampler.magFilter = VK_FILTER_NEAREST;
  sampler.minFilter = VK_FILTER_NEAREST;
  sampler.addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  sampler.addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  sampler.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  vkCheck(vkCreateSampler(device_, &sampler, nullptr, &sampler_), "vkCreateSampler");
  setLayout_ = createSetLayout(device_, {{0, kSampled, kCompute},
                                         {1, kSampled, kCompute},
                                         {2, kSampled, kCompute},
                                         {3, kSampled, kCompute},
                                         {4, kStorageImage, kCompute},
                                         {5, kStorageImage, kCompute},
                                         {6, kStorageImage, kCompute}});
  layout_ = createPipelineLayout(device_, setLayout_, sizeof(Params), kCompute);
  // Dispatched band by band from a base workgroup (vkCmdDispatchBase).
  pipeline_ = createComputePipeline(device_, layout_, ShaderId::kCrackFillComp,
                                    VK_PIPELINE_CREATE_DISPATCH_BASE_BIT);
  pool_ = createPool(device_, 1, {kSampled, kStorageImage}, 4);
  set_ = allocateSet(device_, pool_, setLayout_);
}

CrackFillPass::~CrackFillPass() {
  vkDestroyDescriptorPool(device_, pool_, nullptr);
  vkDestroyPipeline(device_, pipeline_, nullptr);
  vkDestroyPipelineLayout(device_, layout_, nullptr);
  vkDestroyDescriptorSetLayout(device_, setLayout_, nullptr);
  vkDestroySampler(device_, sampler_, nullptr);
}

void CrackFillPass::bind(const RenderTargets& targets) {
  constexpr VkImageLayout kRead = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  constexpr VkImageLayout kWrite = VK_IMAGE_LAYOUT_GENERAL;
  writeImageDescriptor(device_, set_, 0, kSampled, targets.color().view(), kRead, sampler_);
  writeImageDescriptor(device_, set_, 1, kSampled, targets.patchId().view(), kRead, sampler_);
  writeImageDescriptor(device_, set_, 2, kSampled, targets.depth().view(), kRead, sampler_);
  writeImageDescriptor(device_, set_, 3, kSampled, targets.depthRange().view(), kRead, sampler_);
  writeImageDescriptor(device_, set_, 4, kStorageImage, targets.filledColor().view(), kWrite,
                       VK_NULL_HANDLE);
  writeImageDescriptor(device_, set_, 5, kStorageImage, targets.filledPatchId().view(), kWrite,
                       VK_NULL_HANDLE);
  writeImageDescriptor(device_, set_, 6, kStorageImage, targets.filledDepth().view(), kWrite,
                       VK_NULL_HANDLE);
}

void CrackFillPass::record(VkCommandBuffer cmd, const RenderTargets& targets,
                           StageClock& clock) const {
  Params params{static_cast<int32_t>(targets.width()), static_cast<int32_t>(targets.height())};
  const std::vector<RenderTargets::RowBand> bands =
      targets.bands(RenderTargets::kCrackFillBandPixels);
  for (size_t k = 0; k < bands.size(); ++k) {
    if (k > 0) clock.enter(Stage::kCrackFilling);  // a new command buffer: bind again
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
    vkCmdPushConstants(cmd, layout_, kCompute, 0, sizeof(params), &params);
    // Bands start on a workgroup row (RenderTargets::bands keeps them multiples of kTile rows).
    vkCmdDispatchBase(cmd, 0, bands[k].first / kTile, 0, (targets.width() + kTile - 1) / kTile,
                      (bands[k].count + kTile - 1) / kTile, 1);
  }
}

}  // namespace tessera::gpu
