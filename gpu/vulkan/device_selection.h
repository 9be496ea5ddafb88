// Which Vulkan device the renderer runs on, and what it found there.
// Automatic choice: a discrete NVIDIA GPU, else any discrete GPU, else an integrated or
// virtual one, else a CPU implementation (lavapipe). A name substring or an index (the
// position in vkEnumeratePhysicalDevices order) overrides it.
#pragma once

#include <cstdint>
#include <string>

namespace tessera::gpu {

struct DeviceSelection {
  std::string nameContains;  // case-insensitive substring of the device name; empty: automatic
  int index = -1;            // ≥ 0: that physical device; wins over nameContains
  bool validation = false;   // enable VK_LAYER_KHRONOS_validation when it is installed

  // TESSERA_VK_DEVICE (all digits: an index; otherwise a name substring) and
  // TESSERA_VK_VALIDATION=1. Read only here, so the renderer has no hidden global inputs.
  static DeviceSelection fromEnvironment();
};

enum class DeviceKind { kDiscrete, kIntegrated, kVirtual, kCpu, kOther };

struct DeviceInfo {
  std::string name;
  std::string driver;  // driver name and info, e.g. "llvmpipe Mesa 22.3.6 (LLVM 15.0.6)"
  uint32_t index = 0;  // position among the physical devices
  uint32_t vendorId = 0;
  uint32_t deviceId = 0;
  DeviceKind kind = DeviceKind::kOther;
  uint32_t apiVersion = 0;
  bool meshShaders = false;  // VK_EXT_mesh_shader usable with our meshlet size
  uint32_t maxMeshOutputVertices = 0;
  uint32_t maxMeshOutputPrimitives = 0;
  bool timestamps = false;  // graphics/compute queue supports timestamp queries
  bool validation = false;  // validation layer actually enabled
};

const char* deviceKindName(DeviceKind kind);

}  // namespace tessera::gpu
