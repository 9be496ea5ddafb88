// Which CUDA device Tessera would run on: for the tests and benchmarks that need one, and for the
// server's engine choice and server info (server/tessellation/engine_choice.h).
// Plain C++ (no CUDA types). Never throws and never crashes when the driver or the device is
// missing: `available` is false and `reason` says why, in CUDA's own words.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace tessera::cuda {

struct CudaDeviceInfo {
  bool available = false;
  // Empty when available, else CUDA's words, e.g. "cudaGetDeviceCount: no CUDA-capable device
  // is detected (cudaErrorNoDevice)".
  std::string reason;
  int deviceCount = 0;
  int index = 0;
  std::string name;
  size_t totalMemoryBytes = 0;
  int computeMajor = 0, computeMinor = 0;
  int multiprocessors = 0;
  size_t sharedMemoryPerBlockOptIn = 0;
  int l2CacheBytes = 0;
  std::array<uint8_t, 16> uuid{};  // cudaDeviceProp::uuid; equals Vulkan's deviceUUID (MATH.md §6)
  int pciDomain = 0, pciBus = 0, pciDevice = 0;
  int driverVersion = 0;   // e.g. 13000 for 13.0; 0 when no driver is installed
  int runtimeVersion = 0;  // the CUDA runtime Tessera was linked against

  // nvidia-smi's spelling: "GPU-xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx".
  std::string uuidString() const;
  // One line for logs and server info: name, compute capability, memory, UUID; or the reason.
  std::string summary() const;
};

// Device `index` (default: the one the CUDA runtime uses first).
CudaDeviceInfo queryCudaDevice(int index = 0);

}  // namespace tessera::cuda
