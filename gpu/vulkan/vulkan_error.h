// Error types of the Vulkan renderer. Driver failures carry the failing call and the VkResult
// name ("vkAllocateMemory failed: VK_ERROR_OUT_OF_DEVICE_MEMORY") so an operator can act on
// them; bad user input (camera, patches, sizes) and unsupported requests have their own types
// so the server can map them to distinct gRPC statuses.
#pragma once

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace tessera::gpu {

// The name of a VkResult enumerator, e.g. "VK_ERROR_DEVICE_LOST"; unknown values as numbers.
std::string vkResultName(VkResult result);

class VulkanError : public std::runtime_error {
 public:
  VulkanError(const std::string& call, VkResult result);
  const std::string& call() const { return call_; }
  VkResult result() const { return result_; }

 private:
  std::string call_;
  VkResult result_;
};

// Invalid input to the renderer: a camera with NaNs, a zero-sized target, a bad patch.
class RenderInputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// A valid request this device or build cannot serve (mesh path without VK_EXT_mesh_shader,
// no Vulkan 1.3 device, a device override that matches nothing).
class RenderUnsupportedError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws VulkanError unless `result` is VK_SUCCESS (or another non-error code).
inline void vkCheck(VkResult result, const char* call) {
  if (result < 0) throw VulkanError(call, result);
}

}  // namespace tessera::gpu
