// What a physical device offers, asked without creating a logical device: shared by the
// renderer's device choice (vulkan_context.cpp) and the start-up probe (device_probe.cpp), so
// both judge a device by the same checks.
#pragma once

#include <vulkan/vulkan.h>

#include <string>
#include <vector>

#include "gpu/vulkan/device_ranking.h"
#include "gpu/vulkan/device_selection.h"

namespace tessera::gpu {

DeviceKind kindOf(VkPhysicalDeviceType type);
// The first queue family that does graphics and compute (and so transfers), or -1.
int graphicsComputeFamily(VkPhysicalDevice device);
bool hasDeviceExtension(VkPhysicalDevice device, const char* name);
// Empty when the device has Vulkan 1.3 and a graphics+compute queue, else which it lacks: what
// the probe asks of a device, and the first of the renderer's requirements.
std::string missingBasics(VkPhysicalDevice device);
// The instance's physical devices (throws VulkanError when the loader fails).
std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance);
// A device as device ranking sees it: name, vendor, kind, and usable when `whyUnusable` is empty.
DeviceCandidate candidateOf(VkPhysicalDevice device, std::string whyUnusable);

}  // namespace tessera::gpu
