// Which Vulkan device the renderer is expected to use, found cheaply at server start so that
// GetServerInfo can name it before the first frame: an instance and the physical devices'
// properties only, ranked by the renderer's own policy (device_ranking.h, TESSERA_VK_DEVICE
// honoured). No logical device is created: on lavapipe that alone takes ~0.4 s, against
// ~50 ms for this. The renderer's check at the first frame is stricter (Vulkan 1.3 features),
// so the header of every frame names the device that really drew it.
#pragma once

#include <string>

#include "gpu/vulkan/device_selection.h"

namespace tessera::gpu {

struct ProbedDevice {
  std::string name;
  std::string driver;  // driver name and info
  DeviceKind kind = DeviceKind::kOther;
  bool meshShaderExtension = false;  // VK_EXT_mesh_shader advertised (not yet checked in full)
};

// Throws std::runtime_error (no loader or driver) or RenderUnsupportedError (no device
// with Vulkan 1.3 and a graphics+compute queue, or an override that matches none).
ProbedDevice probeRenderDevice(const DeviceSelection& selection);

}  // namespace tessera::gpu
