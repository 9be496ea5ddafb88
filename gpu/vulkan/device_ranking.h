// Choosing a physical device from plain descriptions, apart from Vulkan calls so the policy
// can be tested with made-up device lists.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "gpu/vulkan/device_selection.h"

namespace tessera::gpu {

inline constexpr uint32_t kVendorNvidia = 0x10DE;

struct DeviceCandidate {
  std::string name;
  uint32_t vendorId = 0;
  DeviceKind kind = DeviceKind::kOther;
  bool usable = false;  // Vulkan 1.3 with a graphics+compute queue and the features we need
  std::string whyUnusable;
};

// Lower is better: NVIDIA discrete, other discrete, integrated, virtual, CPU, other.
int deviceRank(const DeviceCandidate& candidate);

// Index of the device to use. Throws RenderUnsupportedError, listing every device and why it
// was passed over, when the override matches nothing usable or no device is usable at all.
size_t chooseDevice(std::span<const DeviceCandidate> candidates, const DeviceSelection& selection);

}  // namespace tessera::gpu
