// The offscreen images one frame renders into and the host buffers it is read back through.
// Raster targets: colour (RGBA8), depth (D32), patch id (R32_UINT) and the covering triangle's
// depth range (RG32F, min and max window depth). The crack filler writes colour, id and depth
// into a second set of images, so its reads never see its own writes.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "gpu/vulkan/gpu_memory.h"
#include "gpu/vulkan/pipeline_builders.h"
#include "gpu/vulkan/render_types.h"
#include "gpu/vulkan/stage_clock.h"

namespace tessera::gpu {

class VulkanContext;

class RenderTargets {
 public:
  static AttachmentFormats formats();

  // Throws RenderUnsupportedError if the device lacks a needed format feature.
  RenderTargets(const VulkanContext& context, uint32_t width, uint32_t height);

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

  // The rows a frame is rasterised and crack-filled in, band by band, whole frames up to a band's
  // pixels. On CPU devices each band is its own submission, so that a large frame can be
  // abandoned between them: raster bands of 4 M pixels (each draws the whole batch again,
  // scissored: 0.2-0.4 s at 8192 wide on lavapipe here, up to 0.8 s with 8 M, and more when the
  // machine is busy), crack-filling bands of 2 M (~0.15 s).
  struct RowBand {
    uint32_t first = 0;
    uint32_t count = 0;
  };
  static constexpr uint32_t kRasterBandPixels = 4u << 20;
  static constexpr uint32_t kCrackFillBandPixels = 2u << 20;
  std::vector<RowBand> bands(uint32_t bandPixels = kRasterBandPixels) const;

  // Recording steps, in frame order.
  void toAttachments(VkCommandBuffer cmd) const;
  void beginRendering(VkCommandBuffer cmd, bool clear,
                      const std::array<float, 4>& background) const;
  // The same, drawing (and clearing) only `band`'s rows; the viewport stays the whole frame.
  void beginRendering(VkCommandBuffer cmd, bool clear, const std::array<float, 4>& background,
                      RowBand band) const;
  void endRendering(VkCommandBuffer cmd) const;
  void toCrackFill(VkCommandBuffer cmd) const;  // raster targets readable, outputs writable
  // Copies colour, depth and (with `patchIds`) patch ids to the host buffers; a frame of several
  // bands copies each image in a stage of its own (`clock`), so that it can be abandoned between.
  void recordReadback(VkCommandBuffer cmd, bool fromCrackFill, bool patchIds,
                      StageClock& clock) const;

  // Copies the read-back pixels into `frame` (after the frame's fence has signalled), 64 MiB at
  // a time with `checkpoint` (may be null, may throw) between: 0.8 GB at 8192 x 8192.
  void copyTo(Frame& frame, bool patchIds, const std::function<void()>& checkpoint) const;

  // Memory the images and readback buffers hold: 44 bytes a pixel on lavapipe.
  VkDeviceSize bytes() const;

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
