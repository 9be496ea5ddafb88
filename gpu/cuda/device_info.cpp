#include "gpu/cuda/device_info.h"

#include <cuda_runtime_api.h>

#include <cstdio>

namespace tessera::cuda {
namespace {

std::string describe(const char* call, cudaError_t status) {
  return std::string(call) + ": " + cudaGetErrorString(status) + " (" + cudaGetErrorName(status) +
         ")";
}

}  // namespace

std::string CudaDeviceInfo::uuidString() const {
  char text[64];
  const uint8_t* u = uuid.data();
  std::snprintf(text, sizeof text,
                "GPU-%02x%02x%02x%02x-%02x%02x-%02x%02x-%02x%02x-%02x%02x%02x%02x%02x%02x", u[0],
                u[1], u[2], u[3], u[4], u[5], u[6], u[7], u[8], u[9], u[10], u[11], u[12], u[13],
                u[14], u[15]);
  return text;
}

std::string CudaDeviceInfo::summary() const {
  if (!available) return "no CUDA device: " + reason;
  char text[160];
  std::snprintf(text, sizeof text, " (sm_%d%d, %d SMs, %.1f GiB, driver %d.%d, runtime %d.%d) ",
                computeMajor, computeMinor, multiprocessors,
                double(totalMemoryBytes) / (1024.0 * 1024.0 * 1024.0), driverVersion / 1000,
                driverVersion % 1000 / 10, runtimeVersion / 1000, runtimeVersion % 1000 / 10);
  return name + text + uuidString();
}

CudaDeviceInfo queryCudaDevice(int index) {
  CudaDeviceInfo info;
  info.index = index;
  // Both version queries work without a device; the driver one reports 0 without a driver.
  cudaDriverGetVersion(&info.driverVersion);
  cudaRuntimeGetVersion(&info.runtimeVersion);

  cudaError_t status = cudaGetDeviceCount(&info.deviceCount);
  if (status != cudaSuccess) {
    info.deviceCount = 0;
    info.reason = describe("cudaGetDeviceCount", status);
    cudaGetLastError();  // leave no sticky error behind for the next caller
    return info;
  }
  if (info.deviceCount == 0) {
    info.reason = "cudaGetDeviceCount found 0 devices";
    return info;
  }
  if (index < 0 || index >= info.deviceCount) {
    info.reason = "device index " + std::to_string(index) + " out of range (" +
                  std::to_string(info.deviceCount) + " devices)";
    return info;
  }
  cudaDeviceProp prop{};
  status = cudaGetDeviceProperties(&prop, index);
  if (status != cudaSuccess) {
    info.reason = describe("cudaGetDeviceProperties", status);
    cudaGetLastError();
    return info;
  }
  info.available = true;
  info.name = prop.name;
  info.totalMemoryBytes = prop.totalGlobalMem;
  info.computeMajor = prop.major;
  info.computeMinor = prop.minor;
  info.multiprocessors = prop.multiProcessorCount;
  info.sharedMemoryPerBlockOptIn = prop.sharedMemPerBlockOptin;
  info.l2CacheBytes = prop.l2CacheSize;
  for (int b = 0; b < 16; ++b) info.uuid[b] = uint8_t(prop.uuid.bytes[b]);
  info.pciDomain = prop.pciDomainID;
  info.pciBus = prop.pciBusID;
  info.pciDevice = prop.pciDeviceID;
  return info;
}

}  // namespace tessera::cuda
