// Buffers and images with their own device memory (one allocation each: the renderer holds a
// handful of large objects, so a sub-allocator would buy nothing). Move-only RAII.
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>

namespace tessera::gpu {

class VulkanContext;

enum class MemoryUse {
  kDeviceOnly,  // written and read by the GPU only
  kUpload,      // written by the host every frame, read by the GPU
  kReadback,    // written by the GPU, read by the host
};

class GpuBuffer {
 public:
  GpuBuffer() = default;
  GpuBuffer(const VulkanContext& context, VkDeviceSize size, VkBufferUsageFlags usage,
            MemoryUse use);
  ~GpuBuffer();
  GpuBuffer(GpuBuffer&& other) noexcept;
  GpuBuffer& operator=(GpuBuffer&& other) noexcept;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }  // host-visible buffers stay mapped
  // Makes host writes visible to the device / device writes visible to the host where the
  // memory is not coherent.
  void flush() const;
  void invalidate() const;

 private:
  void release();
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
  bool coherent_ = true;
};

class GpuImage {
 public:
  GpuImage() = default;
  GpuImage(const VulkanContext& context, VkFormat format, uint32_t width, uint32_t height,
           VkImageUsageFlags usage, VkImageAspectFlags aspect);
  ~GpuImage();
  GpuImage(GpuImage&& other) noexcept;
  GpuImage& operator=(GpuImage&& other) noexcept;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }
  VkFormat format() const { return format_; }
  VkImageAspectFlags aspect() const { return aspect_; }
  VkDeviceSize size() const { return size_; }  // of its memory; 0 when empty

 private:
  void release();
  VkDevice device_ = VK_NULL_HANDLE;
  VkImage image_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkImageAspectFlags aspect_ = 0;
  VkDeviceSize size_ = 0;
};

}  // namespace tessera::gpu
