#include "gpu/vulkan/render_targets.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "gpu/vulkan/barriers.h"
#include "gpu/vulkan/vulkan_context.h"
#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace {

constexpr VkFormat kColor = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kPatchId = VK_FORMAT_R32_UINT;
constexpr VkFormat kDepthRange = VK_FORMAT_R32G32_SFLOAT;
constexpr VkFormat kDepth = VK_FORMAT_D32_SFLOAT;
constexpr VkFormat kFilledDepth = VK_FORMAT_R32_SFLOAT;

constexpr VkImageAspectFlags kColorAspect = VK_IMAGE_ASPECT_COLOR_BIT;
constexpr VkImageAspectFlags kDepthAspect = VK_IMAGE_ASPECT_DEPTH_BIT;

void requireFormat(const VulkanContext& context, VkFormat format, VkFormatFeatureFlags features,
                   const char* what) {
  VkFormatProperties props;
  vkGetPhysicalDeviceFormatProperties(context.physicalDevice(), format, &props);
  if ((props.optimalTilingFeatures & features) != features) {
    throw RenderUnsupportedError(std::string("device cannot use format ") + what +
                                 " for the render targets");
  }
}

constexpr Access kNothing{VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE};
constexpr Access kColorWrite{
    VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT};
constexpr Access kDepthWrite{
    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT};
constexpr Access kComputeRead{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                              VK_ACCESS_2_SHADER_SAMPLED_READ_BIT};
constexpr Access kComputeWrite{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                               VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT};
constexpr Access kTransferRead{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT};
constexpr Access kTransferWrite{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT};
constexpr Access kHostRead{VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT};

void copyImage(VkCommandBuffer cmd, const GpuImage& image, const GpuBuffer& buffer, uint32_t width,
               uint32_t height) {
  VkBufferImageCopy region{};
  region.imageSubresource = {image.aspect(), 0, 0, 1};
  region.imageExtent = {width, height, 1};
  vkCmdCopyImageToBuffer(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.handle(),
                         1, &region);
}

}  // namespace

AttachmentFormats RenderTargets::formats() {
  return {{kColor, kPatchId, kDepthRange}, kDepth};
}

RenderTargets::RenderTargets(const VulkanContext& context, uint32_t width, uint32_t height)
    : width_(width), height_(height) {
  constexpr VkFormatFeatureFlags kAttachment =
      VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
  requireFormat(context, kColor, kAttachment | VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT, "RGBA8");
  requireFormat(context, kPatchId, kAttachment | VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT, "R32_UINT");
  requireFormat(context, kDepthRange, kAttachment, "RG32F");
  requireFormat(
      context, kDepth,
      VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT, "D32");
  requireFormat(context, kFilledDepth, VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT, "R32F");

  constexpr VkImageUsageFlags kRaster = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
                                        VK_IMAGE_USAGE_SAMPLED_BIT |
                                        VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  constexpr VkImageUsageFlags kFilled =
      VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  color_ = GpuImage(context, kColor, width, height, kRaster, kColorAspect);
  patchId_ = GpuImage(context, kPatchId, width, height, kRaster, kColorAspect);
  depthRange_ = GpuImage(context, kDepthRange, width, height, kRaster, kColorAspect);
  depth_ = GpuImage(context, kDepth, width, height,
                    VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                        VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                    kDepthAspect);
  filledColor_ = GpuImage(context, kColor, width, height, kFilled, kColorAspect);
  filledPatchId_ = GpuImage(context, kPatchId, width, height, kFilled, kColorAspect);
  filledDepth_ = GpuImage(context, kFilledDepth, width, height, kFilled, kColorAspect);

  VkDeviceSize bytes = VkDeviceSize(width) * height * 4;
  constexpr VkBufferUsageFlags kDst = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  colorReadback_ = GpuBuffer(context, bytes, kDst, MemoryUse::kReadback);
  patchIdReadback_ = GpuBuffer(context, bytes, kDst, MemoryUse::kReadback);
  depthReadback_ = GpuBuffer(context, bytes, kDst, MemoryUse::kReadback);
}

void RenderTargets::toAttachments(VkCommandBuffer cmd) const {
  // The previous contents are discarded (UNDEFINED): every frame starts with a clear.
  for (const GpuImage* image : {&color_, &patchId_, &depthRange_}) {
    imageBarrier(cmd, image->handle(), kColorAspect, VK_IMAGE_LAYOUT_UNDEFINED,
                 VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, kTransferRead, kColorWrite);
  }
  imageBarrier(cmd, depth_.handle(), kDepthAspect, VK_IMAGE_LAYOUT_UNDEFINED,
               VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, kTransferRead, kDepthWrite);
}

std::vector<RenderTargets::RowBand> RenderTargets::bands(uint32_t bandPixels) const {
  constexpr uint32_t kRowAlignment = 8;  // crack_fill.comp's workgroup height
  const uint32_t rows =
      std::max(kRowAlignment, (bandPixels / width_) / kRowAlignment * kRowAlignment);
  std::vector<RowBand> out;
  for (uint32_t first = 0; first < height_; first += rows)
    out.push_back({first, std::min(rows, height_ - first)});
  return out;
}

void RenderTargets::beginRendering(VkCommandBuffer cmd, bool clear,
                                   const std::array<float, 4>& background) const {
  beginRendering(cmd, clear, background, RowBand{0, height_});
}

void RenderTargets::beginRendering(VkCommandBuffer cmd, bool clear,
                                   const std::array<float, 4>& background, RowBand band) const {
  VkRenderingAttachmentInfo colors[3]{};
  const GpuImage* images[3] = {&color_, &patchId_, &depthRange_};
  VkClearValue clears[3]{};
  for (int i = 0; i < 4; ++i) clears[0].color.float32[i] = background[i];
  clears[1].color.uint32[0] = kBackgroundPatchId;
  clears[2].color.float32[0] = 1.0f;  // an empty pixel's "triangle" lies at the far plane
  clears[2].color.float32[1] = 1.0f;
  for (int i = 0; i < 3; ++i) {
    colors[i].sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
    colors[i].imageView = images[i]->view();
    colors[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colors[i].loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
    colors[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    colors[i].clearValue = clears[i];
  }
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = depth_.view();
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  depth.clearValue.depthStencil = {1.0f, 0};

  VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
  info.renderArea = {{0, int32_t(band.first)}, {width_, band.count}};
  info.layerCount = 1;
  info.colorAttachmentCount = 3;
  info.pColorAttachments = colors;
  info.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &info);
  VkViewport viewport{0.0f, 0.0f, float(width_), float(height_), 0.0f, 1.0f};
  VkRect2D scissor{{0, int32_t(band.first)}, {width_, band.count}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

void RenderTargets::endRendering(VkCommandBuffer cmd) const {
  vkCmdEndRendering(cmd);
}

void RenderTargets::toCrackFill(VkCommandBuffer cmd) const {
  for (const GpuImage* image : {&color_, &patchId_, &depthRange_}) {
    imageBarrier(cmd, image->handle(), kColorAspect, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                 VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, kColorWrite, kComputeRead);
  }
  imageBarrier(cmd, depth_.handle(), kDepthAspect, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
               VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, kDepthWrite, kComputeRead);
  for (const GpuImage* image : {&filledColor_, &filledPatchId_, &filledDepth_}) {
    imageBarrier(cmd, image->handle(), kColorAspect, VK_IMAGE_LAYOUT_UNDEFINED,
                 VK_IMAGE_LAYOUT_GENERAL, kTransferRead, kComputeWrite);
  }
}

void RenderTargets::recordReadback(VkCommandBuffer cmd, bool fromCrackFill, bool patchIds,
                                   StageClock& clock) const {
  const GpuImage& color = fromCrackFill ? filledColor_ : color_;
  const GpuImage& patchId = fromCrackFill ? filledPatchId_ : patchId_;
  const GpuImage& depth = fromCrackFill ? filledDepth_ : depth_;
  if (fromCrackFill) {
    for (const GpuImage* image : {&color, &patchId, &depth}) {
      imageBarrier(cmd, image->handle(), kColorAspect, VK_IMAGE_LAYOUT_GENERAL,
                   VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, kComputeWrite, kTransferRead);
    }
  } else {
    for (const GpuImage* image : {&color, &patchId}) {
      imageBarrier(cmd, image->handle(), kColorAspect, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                   VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, kColorWrite, kTransferRead);
    }
    imageBarrier(cmd, depth.handle(), kDepthAspect, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                 VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, kDepthWrite, kTransferRead);
  }
  const bool split = bands().size() > 1;
  copyImage(cmd, color, colorReadback_, width_, height_);
  if (split) clock.enter(Stage::kReadback);
  copyImage(cmd, depth, depthReadback_, width_, height_);
  if (patchIds) {
    if (split) clock.enter(Stage::kReadback);
    copyImage(cmd, patchId, patchIdReadback_, width_, height_);
  }
  memoryBarrier(cmd, kTransferWrite, kHostRead);
}

VkDeviceSize RenderTargets::bytes() const {
  VkDeviceSize total = colorReadback_.size() + patchIdReadback_.size() + depthReadback_.size();
  for (const GpuImage* image :
       {&color_, &patchId_, &depthRange_, &depth_, &filledColor_, &filledPatchId_, &filledDepth_}) {
    total += image->size();
  }
  return total;
}

namespace {

// memcpy in slices, polling between them.
void copyInSlices(void* to, const void* from, size_t bytes,
                  const std::function<void()>& checkpoint) {
  constexpr size_t kSlice = 64 << 20;
  for (size_t offset = 0; offset < bytes; offset += kSlice) {
    if (checkpoint) checkpoint();
    std::memcpy(static_cast<uint8_t*>(to) + offset, static_cast<const uint8_t*>(from) + offset,
                std::min(kSlice, bytes - offset));
  }
}

}  // namespace

void RenderTargets::copyTo(Frame& frame, bool patchIds,
                           const std::function<void()>& checkpoint) const {
  size_t pixels = size_t(width_) * height_;
  frame.width = width_;
  frame.height = height_;
  colorReadback_.invalidate();
  depthReadback_.invalidate();
  frame.rgba.resize(pixels * 4);
  copyInSlices(frame.rgba.data(), colorReadback_.mapped(), pixels * 4, checkpoint);
  frame.depth.resize(pixels);
  copyInSlices(frame.depth.data(), depthReadback_.mapped(), pixels * 4, checkpoint);
  if (!patchIds) return;
  patchIdReadback_.invalidate();
  frame.patchIds.resize(pixels);
  copyInSlices(frame.patchIds.data(), patchIdReadback_.mapped(), pixels * 4, checkpoint);
}

}  // namespace tessera::gpu
