// The offscreen images one frame renders into and the host buffers it is read back through.
// Raster targets: colour (RGBA8), depth (D32), patch id (R32_UINT) and the covering triangle's
// depth range (RG32F, min and max window depth). The crack filler writes colour, id and depth
// into a second set of images, so its reads never see its own writes.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>

#include "gpu/vulkan/gpu_memory.h"
#include "gpu/vulkan/pipeline_builders.h"
#include "gpu/vulkan/render_types.h"

namespace tessera::gpu {

class VulkanContext;

class RenderTargets {
 public:
  static AttachmentFormats formats();

  // Throws RenderUnsupportedError if the device lacks a needed format feature.
  RenderTargets(const VulkanContext& context, uint32_t width, uint32_t height);

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

  // Recording steps, in frame order.
  void toAttachments(VkCommandBuffer cmd) const;
  void beginRendering(VkCommandBuffer cmd, bool clear,
                      const std::array<float, 4>& background) const;
  void endRendering(VkCommandBuffer cmd) const;
  void toCrackFill(VkCommandBuffer cmd) const;  // raster targets readable, outputs writable
  void recordReadback(VkCommandBuffer cmd, bool fromCrackFill) const;

  // Copies the read-back pixels into `frame` (after the frame's fence has signalled).
  void copyTo(Frame& frame) const;

  const GpuImage& color() const { return color_; }
  const GpuImage& patchId() const { return patchId_; }
  const GpuImage& depth() const { return depth_; }
  const GpuImage& depthRange() const { return depthRange_; }
  const GpuImage& filledColor() const { return filledColor_; }
  const GpuImage& filledPatchId() const { return filledPatchId_; }
  const GpuImage& filledDepth() const { return filledDepth_; }

 private:
  uint32_t width_;
  uint32_t height_;
  GpuImage color_, patchId_, depthRange_, depth_;
  GpuImage filledColor_, filledPatchId_, filledDepth_;
  GpuBuffer colorReadback_, patchIdReadback_, depthReadback_;
};

}  // namespace tessera::gpu
