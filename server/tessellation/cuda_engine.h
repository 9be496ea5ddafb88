// The CUDA tessellation engine: the CPU engine's job (server/tessellation/cpu_engine.h) with
// every vertex evaluated on the GPU (gpu/cuda/cuda_surface.h), each mesh's surface tree uploaded
// once and kept in device memory under its own byte budget (least recently used evicted). Planning,
// stitching, triangulation and encoding stay on the CPU; the GLB equals the CPU engine's byte for
// byte. A job the device cannot hold (device memory exhausted) runs on the CPU instead. Built
// only with CUDA (server/CMakeLists.txt).
#pragma once

#include <atomic>
#include <string>

#include "gpu/cuda/cuda_surface.h"
#include "gpu/cuda/device_info.h"
#include "server/meshes/lru_cache.h"
#include "server/tessellation/cpu_engine.h"

namespace tessera::server {

class CudaTessellationEngine : public CpuTessellationEngine {
 public:
  // `device` must be available (makeEngine checks).
  CudaTessellationEngine(PatchSetCache& patches, cuda::CudaDeviceInfo device, size_t deviceCacheBytes);
  std::string name() const override { return "cuda"; }
  bool available() const override { return true; }
  std::string detail() const override;
  std::string device() const override { return device_.summary(); }
  TessellationOutput run(const ControlMesh& mesh, const TessellationJob& job,
                         const CancellationToken& cancel) override;

  CacheStats deviceCacheStats() const { return surfaces_.stats(); }
  // Jobs run on the CPU because the device was out of memory.
  uint64_t cpuFallbacks() const { return fallbacks_.load(); }

 private:
  std::shared_ptr<const cuda::CudaSurface> surfaceFor(const std::shared_ptr<const PatchSet>& patches,
                                                      const std::string& key);

  cuda::CudaDeviceInfo device_;
  LruCache<std::string, cuda::CudaSurface> surfaces_;
  std::atomic<uint64_t> fallbacks_{0};
};

}  // namespace tessera::server
