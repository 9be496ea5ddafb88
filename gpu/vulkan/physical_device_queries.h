// What a physical device offers, asked without creating a logical device: shared by the
// renderer's device choice (vulkan_context.cpp) and the start-up probe (device_probe.cpp), so
// both judge a device by the same checks.
#pragma once

#include <vulkan/vulkan.h>

#include "gpu/vulkan/device_selection.h"

namespace tessera::gpu {

DeviceKind kindOf(VkPhysicalDeviceType type);
// The first queue family that does graphics and compute (and so transfers), or -1.
int graphicsComputeFamily(VkPhysicalDevice device);
bool hasDeviceExtension(VkPhysicalDevice device, const char* name);

}  // namespace tessera::gpu
