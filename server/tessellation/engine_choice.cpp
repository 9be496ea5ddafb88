#include "server/tessellation/engine_choice.h"

#include <stdexcept>

#include "server/tessellation/cpu_engine.h"
#if TESSERA_WITH_CUDA
#include "gpu/cuda/device_info.h"
#include "server/tessellation/cuda_engine.h"
#endif

namespace tessera::server {

std::unique_ptr<TessellationEngine> chooseEngine(const std::string& wanted, size_t deviceCacheBytes,
                                                 PatchSetCache& patches) {
  if (wanted == "cpu") return std::make_unique<CpuTessellationEngine>(patches);
#if TESSERA_WITH_CUDA
  cuda::CudaDeviceInfo device = cuda::queryCudaDevice();
  if (device.available) return std::make_unique<CudaTessellationEngine>(patches, std::move(device), deviceCacheBytes);
  const std::string why = "no CUDA device: " + device.reason;
#else
  (void)deviceCacheBytes;
  const std::string why = "this build has no CUDA (no nvcc was found when it was configured)";
#endif
  if (wanted == "cuda") throw std::runtime_error("--engine cuda: " + why);
  return std::make_unique<CpuTessellationEngine>(patches, "--engine auto: " + why);
}

void registerEngineMetrics(MetricsRegistry& registry, const TessellationEngine& engine) {
  registry.info("tessera_engine_info", "The tessellation engine and the accelerator it runs on (empty: none).",
                {"engine", "device"}, {engine.name(), engine.device()});
#if TESSERA_WITH_CUDA
  if (const auto* gpu = dynamic_cast<const CudaTessellationEngine*>(&engine)) {
    registry.sampled("tessera_device_cache_bytes", "GPU memory held by cached surface trees.", "gauge",
                     [gpu] { return double(gpu->deviceCacheStats().bytes); });
    registry.sampled("tessera_device_cpu_fallbacks_total",
                     "Jobs whose vertices were evaluated on the CPU because the GPU was out of memory.", "counter",
                     [gpu] { return double(gpu->cpuFallbacks()); });
  }
#endif
}

}  // namespace tessera::server
