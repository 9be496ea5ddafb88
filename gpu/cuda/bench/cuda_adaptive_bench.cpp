// tessera-cuda-adaptive: the user's job (a tolerance, patch set cached) with its vertices on a
// CUDA device beside the CPU engine, in one process: for each model and tolerance, tessellate +
// GLB on all CPU cores, the same with CudaVertexEvaluation (requests up, kernel, results down),
// the kernel's own time (CUDA events) and the surface tree's one-time upload. The two meshes are
// compared bit for bit first, so a wrong kernel cannot report a time; exits 1 if any differs.
//
// Usage: tessera-cuda-adaptive [--tolerances 1e-2,1e-3,1e-4] [--models bigguy,car]
// Models are read from TESSERA_MODELS_DIR (default: the checkout's ../shared/models).
#include <tbb/info.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/output/glb_writer.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
#include "gpu/cuda/bench/bench_timing.h"
#include "gpu/cuda/cuda_surface.h"
#include "gpu/cuda/device_info.h"
#include "reference/models.h"

namespace {

using namespace tessera;
using namespace cuda::bench;

TessellationOptions optionsFor(double tolerance, VertexEvaluation* evaluation) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(tolerance);
  options.maxTriangles = 200'000'000;
  options.vertexEvaluation = evaluation;
  return options;
}

bool sameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  return a.indices == b.indices && a.positions.size() == b.positions.size() &&
         std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(Vec3)) == 0 &&
         std::memcmp(a.normals.data(), b.normals.data(), a.normals.size() * sizeof(Vec3)) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> tolerances = {1e-2, 1e-3, 1e-4};
  std::vector<std::string> models = {"bigguy", "monsterfrog", "armorguy", "t-rex", "car"};
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--tolerances")) {
      tolerances.clear();
      for (const std::string& item : split(argv[i + 1])) tolerances.push_back(std::stod(item));
    } else if (!std::strcmp(argv[i], "--models")) {
      models = split(argv[i + 1]);
    } else {
      std::fprintf(stderr, "usage: %s [--tolerances 1e-2,1e-3] [--models a,b]\n", argv[0]);
      return 2;
    }
  }
  const cuda::CudaDeviceInfo device = cuda::queryCudaDevice();
  std::printf("device: %s\n", device.summary().c_str());
  if (!device.available) return 1;
  std::printf("CPU: %d TBB threads; medians of 7 calls of tessellate + GLB, patch set cached\n\n",
              tbb::info::default_concurrency());
  std::printf("| model | ε | vertices | triangles | CPU ms | CUDA engine ms | kernel ms | tree upload ms | "
              "tree MB | CPU / CUDA | equal |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  bool allEqual = true;
  for (const std::string& name : models) {
    const ControlMesh mesh = readObjFile(tessera::testing::modelsDir() + "/" + name + ".obj");
    const PatchSet patches = buildPatchSet(mesh);
    const Clock::time_point uploadStart = Clock::now();
    const cuda::CudaSurface surface(patches);
    const double uploadMs = msSince(uploadStart);
    cuda::CudaVertexEvaluation evaluation(surface);
    for (double tolerance : tolerances) {
      const TessellationResult cpu = tessellate(patches, mesh, optionsFor(tolerance, nullptr));
      const TessellationResult gpu = tessellate(patches, mesh, optionsFor(tolerance, &evaluation));
      const bool equal = sameMesh(cpu.mesh, gpu.mesh);
      allEqual = allEqual && equal;
      auto job = [&](VertexEvaluation* e) {
        return [&, e] { writeGlb(tessellate(patches, mesh, optionsFor(tolerance, e)).mesh, {}); };
      };
      const double cpuMs = medianMs(7, job(nullptr));
      const double cudaMs = medianMs(7, job(&evaluation));
      std::printf("| %s | %g | %zu | %zu | %.2f | %.2f | %.3f | %.1f | %.1f | %.2f | %s |\n", name.c_str(), tolerance,
                  cpu.mesh.positions.size(), cpu.mesh.triangleCount(), cpuMs, cudaMs, evaluation.kernelMs(), uploadMs,
                  double(surface.deviceBytes()) / 1e6, cpuMs / cudaMs, equal ? "bit for bit" : "DIFFER");
      std::fflush(stdout);
    }
  }
  return allEqual ? 0 : 1;
}
