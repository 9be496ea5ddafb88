#include "server/tessellation/cuda_engine.h"

#include <spdlog/spdlog.h>

#include <utility>

namespace tessera::server {

namespace {

// A request's evaluation holding the surface it runs on (which the cache may drop meanwhile).
// A device out of memory hands the vertices back to the CPU.
class DeviceVertices : public VertexEvaluation {
 public:
  DeviceVertices(std::shared_ptr<const cuda::CudaSurface> surface, std::function<void(const char*)> fallBack)
      : surface_(std::move(surface)), evaluation_(*surface_), fallBack_(std::move(fallBack)) {}
  bool evaluate(const AdaptivePlan& plan, const Stitching& stitching, std::vector<Vec3>& positions,
                std::vector<Vec3>& normals) override {
    try {
      return evaluation_.evaluate(plan, stitching, positions, normals);
    } catch (const cuda::DeviceOutOfMemory& error) {
      fallBack_(error.what());
      return false;
    }
  }

 private:
  std::shared_ptr<const cuda::CudaSurface> surface_;
  cuda::CudaVertexEvaluation evaluation_;
  std::function<void(const char*)> fallBack_;
};

}  // namespace

CudaTessellationEngine::CudaTessellationEngine(PatchSetCache& patches, cuda::CudaDeviceInfo device,
                                               size_t deviceCacheBytes)
    : CpuTessellationEngine(patches), device_(std::move(device)), surfaces_(deviceCacheBytes) {}

std::string CudaTessellationEngine::detail() const {
  return "EBOAT with the vertices on the CUDA device; OpenSubdiv Far preprocessing, CER FAS, planning and "
         "watertight triangulation on the CPU";
}

std::shared_ptr<const cuda::CudaSurface> CudaTessellationEngine::surfaceFor(
    const std::shared_ptr<const PatchSet>& patches, const std::string& key) {
  if (auto cached = surfaces_.find(key)) return cached;
  auto surface = std::make_shared<const cuda::CudaSurface>(*patches);
  surfaces_.insert(key, surface, surface->deviceBytes());
  return surface;
}

TessellationOutput CudaTessellationEngine::run(const ControlMesh& mesh, const TessellationJob& job,
                                               const CancellationToken& cancel) {
  // Other jobs' surfaces hold the device: this job's vertices are evaluated on the CPU instead,
  // the same values.
  auto fallBack = [this, id = job.meshId](const char* why) {
    fallbacks_.fetch_add(1);
    spdlog::warn("mesh {}: {}; evaluating its vertices on the CPU", id, why);
  };
  return runWith(mesh, job, cancel,
                 [&](const std::shared_ptr<const PatchSet>& patches, const TessellationJob& j)
                     -> std::unique_ptr<VertexEvaluation> {
                   try {
                     return std::make_unique<DeviceVertices>(surfaceFor(patches, j.meshSha256), fallBack);
                   } catch (const cuda::DeviceOutOfMemory& error) {
                     fallBack(error.what());
                     return nullptr;
                   }
                 });
}

}  // namespace tessera::server
