// Internal to gpu/cuda: what every host-side file of the backend needs from the CUDA runtime
// (failed calls as exceptions naming the call, owned device arrays, the device check). Uses CUDA
// runtime types; code outside gpu/cuda sees only the plain C++ headers.
#pragma once

#include <cuda_runtime_api.h>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/base/error.h"
#include "gpu/cuda/device_out_of_memory.h"

namespace tessera::cuda::detail {

// Throws std::runtime_error "<component>: <what> failed: <name> (<description>)"; a device out
// of memory throws DeviceOutOfMemory (a kLimitExceeded TesseraError) instead, so that a caller
// can fall back or answer RESOURCE_EXHAUSTED.
inline void checkCuda(cudaError_t status, const char* component, const char* what) {
  if (status == cudaErrorMemoryAllocation) {
    cudaGetLastError();  // not sticky: clear it for the next call on this thread
    throw DeviceOutOfMemory(std::string(component) + ": " + what + " failed: device memory exhausted (" +
                            cudaGetErrorName(status) + ")");
  }
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

// A device array allocated in stream order (cudaMallocAsync: from the device's memory pool,
// without the device-wide synchronization cudaMalloc and cudaFree bring, so concurrent requests on
// their own streams do not wait for each other) and freed in stream order when destroyed. Destroy
// it before its stream is synchronized and destroyed.
template <class T>
class StreamArray {
 public:
  StreamArray(size_t count, cudaStream_t stream, const char* component, const char* what) : stream_(stream) {
    if (count > 0) checkCuda(cudaMallocAsync(reinterpret_cast<void**>(&data_), count * sizeof(T), stream), component, what);
  }
  // Allocated and filled from host memory.
  StreamArray(const T* host, size_t count, cudaStream_t stream, const char* component, const char* what)
      : StreamArray(count, stream, component, what) {
    if (count > 0) {
      checkCuda(cudaMemcpyAsync(data_, host, count * sizeof(T), cudaMemcpyHostToDevice, stream), component, what);
    }
  }
  ~StreamArray() {
    if (data_ != nullptr) cudaFreeAsync(data_, stream_);
  }
  StreamArray(const StreamArray&) = delete;
  StreamArray& operator=(const StreamArray&) = delete;
  T* get() const { return data_; }

 private:
  cudaStream_t stream_;
  T* data_ = nullptr;
};

// A non-blocking stream and two events to time what is enqueued on it. Destroying it waits for
// the stream first, so declare it after the device arrays its kernels use (members are destroyed
// in reverse order).
class TimedStream {
 public:
  explicit TimedStream(const char* component) : component_(component) {
    try {
      checkCuda(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), component,
                "cudaStreamCreate");
      checkCuda(cudaEventCreate(&start_), component, "cudaEventCreate");
      checkCuda(cudaEventCreate(&stop_), component, "cudaEventCreate");
    } catch (...) {
      release();
      throw;
    }
  }
  ~TimedStream() { release(); }
  TimedStream(const TimedStream&) = delete;
  TimedStream& operator=(const TimedStream&) = delete;

  cudaStream_t get() const { return stream_; }

  // Mean milliseconds per call of `enqueue` over `repetitions` back-to-back calls, measured by
  // the two events around them (the kernels alone, no transfers).
  template <class Enqueue>
  float meanMs(int repetitions, Enqueue&& enqueue) {
    checkCuda(cudaEventRecord(start_, stream_), component_, "cudaEventRecord");
    for (int r = 0; r < repetitions; ++r) enqueue();
    checkCuda(cudaEventRecord(stop_, stream_), component_, "cudaEventRecord");
    checkCuda(cudaEventSynchronize(stop_), component_, "cudaEventSynchronize");
    float milliseconds = 0.0f;
    checkCuda(cudaEventElapsedTime(&milliseconds, start_, stop_), component_,
              "cudaEventElapsedTime");
    return milliseconds / float(repetitions);
  }

  // Enqueues `enqueue` between the two events, without waiting; elapsedMs() reads their time once
  // the stream has been synchronized.
  template <class Enqueue>
  void timeWithoutWaiting(Enqueue&& enqueue) {
    checkCuda(cudaEventRecord(start_, stream_), component_, "cudaEventRecord");
    enqueue();
    checkCuda(cudaEventRecord(stop_, stream_), component_, "cudaEventRecord");
  }
  float elapsedMs() {
    float milliseconds = 0.0f;
    checkCuda(cudaEventElapsedTime(&milliseconds, start_, stop_), component_, "cudaEventElapsedTime");
    return milliseconds;
  }

  // Waits for the stream; a fault of a kernel on it is reported here, naming `what`.
  void synchronize(const char* what) {
    checkCuda(cudaStreamSynchronize(stream_), component_, what);
  }

 private:
  void release() {
    if (stream_ != nullptr) cudaStreamSynchronize(stream_);
    if (start_ != nullptr) cudaEventDestroy(start_);
    if (stop_ != nullptr) cudaEventDestroy(stop_);
    if (stream_ != nullptr) cudaStreamDestroy(stream_);
  }

  const char* component_;
  cudaStream_t stream_ = nullptr;
  cudaEvent_t start_ = nullptr, stop_ = nullptr;
};

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
