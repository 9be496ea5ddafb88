// The headless Vulkan 1.3 instance and device the renderer runs on: no surface, no swapchain,
// one queue that does graphics, compute and transfers. Owns the objects every pass shares.
#pragma once

#include <vulkan/vulkan.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "gpu/vulkan/device_selection.h"

namespace tessera::gpu {

class VulkanContext {
 public:
  static std::unique_ptr<VulkanContext> create(const DeviceSelection& selection);
  ~VulkanContext();
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  VkCommandPool commandPool() const { return commandPool_; }
  const DeviceInfo& info() const { return info_; }
  const VkPhysicalDeviceLimits& limits() const { return limits_; }
  const VkPhysicalDeviceMemoryProperties& memoryProperties() const { return memory_; }
  PFN_vkCmdDrawMeshTasksEXT drawMeshTasks() const { return drawMeshTasks_; }

  // Validation-layer warnings and errors since the last call (empty without validation).
  std::vector<std::string> takeValidationMessages();

 private:
  VulkanContext() = default;
  void createInstance(bool wantValidation);
  void pickPhysicalDevice(const DeviceSelection& selection);
  void createDevice();

  static VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(
      VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
      const VkDebugUtilsMessengerCallbackDataEXT* data, void* self);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queueFamily_ = 0;
  VkCommandPool commandPool_ = VK_NULL_HANDLE;
  DeviceInfo info_;
  VkPhysicalDeviceLimits limits_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  PFN_vkCmdDrawMeshTasksEXT drawMeshTasks_ = nullptr;
  std::mutex messagesMutex_;
  std::vector<std::string> messages_;
};

}  // namespace tessera::gpu
