// Internal to gpu/cuda: what every host-side file of the backend needs from the CUDA runtime
// (failed calls as exceptions naming the call, owned device arrays, the device check). Uses CUDA
// runtime types; code outside gpu/cuda sees only the plain C++ headers.
#pragma once

#include <cuda_runtime_api.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "core/error.h"

namespace tessera::cuda::detail {

// Throws std::runtime_error "<component>: <what> failed: <name> (<description>)".
inline void checkCuda(cudaError_t status, const char* component, const char* what) {
  if (status != cudaSuccess) {
    throw std::runtime_error(std::string(component) + ": " + what + " failed: " +
                             cudaGetErrorName(status) + " (" + cudaGetErrorString(status) + ")");
  }
}

struct DeviceFree {
  void operator()(void* pointer) const { cudaFree(pointer); }
};
template <class T>
using DeviceArray = std::unique_ptr<T, DeviceFree>;

template <class T>
DeviceArray<T> allocateDevice(size_t count, const char* component, const char* what) {
  void* pointer = nullptr;
  if (count > 0) checkCuda(cudaMalloc(&pointer, count * sizeof(T)), component, what);
  return DeviceArray<T>(static_cast<T*>(pointer));
}

template <class T>
DeviceArray<T> uploadToDevice(const T* host, size_t count, const char* component,
                              const char* what) {
  DeviceArray<T> array = allocateDevice<T>(count, component, what);
  if (count > 0) {
    checkCuda(cudaMemcpy(array.get(), host, count * sizeof(T), cudaMemcpyHostToDevice), component,
              what);
  }
  return array;
}

// Throws TesseraError(kUnsupported, "no CUDA device: <CUDA's reason>") when there is none.
inline void requireCudaDevice() {
  int devices = 0;
  const cudaError_t status = cudaGetDeviceCount(&devices);
  if (status != cudaSuccess) {
    cudaGetLastError();
    throwUnsupported(std::string("no CUDA device: ") + cudaGetErrorString(status) + " (" +
                     cudaGetErrorName(status) + ")");
  }
  if (devices == 0) throwUnsupported("no CUDA device: cudaGetDeviceCount found 0 devices");
}

}  // namespace tessera::cuda::detail
