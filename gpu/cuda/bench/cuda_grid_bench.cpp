// tessera-cuda-table2: the paper's Table 2 (§6.1) workload on a CUDA device beside the CPU, in
// one process on one machine: for each model and uniform level p, the CPU's planUniformGrid (FAS
// of every ring, the pieces and their nets; TBB over all cores) and evaluateUniformGrid (AVX2,
// TBB), and the GPU's evaluation of the same pieces from the same nets into device memory
// (kernel time with CUDA events, mean of several launches after a warm-up; the upload of nets,
// pieces and offsets timed apart). The GPU output is compared with the CPU's bit for bit first,
// so a wrong kernel cannot report a fast time; the program exits 1 if any sample differs.
//
// Usage: tessera-cuda-table2 [--levels 16,32,64] [--repetitions R] [--models bigguy,car]
// Models are read from TESSERA_MODELS_DIR (default: the checkout's ../shared/models).
#include <tbb/info.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/uniform/uniform_grid.h"
#include "gpu/cuda/bench/bench_timing.h"
#include "gpu/cuda/cuda_uniform_grid.h"
#include "gpu/cuda/device_info.h"
#include "reference/models.h"

namespace {

using namespace tessera;
using namespace cuda::bench;

struct Options {
  std::vector<int> levels = {16, 32, 64};
  int repetitions = 20;
  std::vector<std::string> models = {"bigguy", "monsterfrog", "armorguy", "t-rex", "car"};
};

bool parse(int argc, char** argv, Options& options) {
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--levels")) {
      options.levels.clear();
      for (const std::string& item : split(argv[i + 1])) options.levels.push_back(std::stoi(item));
    } else if (!std::strcmp(argv[i], "--repetitions")) {
      options.repetitions = std::atoi(argv[i + 1]);
    } else if (!std::strcmp(argv[i], "--models")) {
      options.models = split(argv[i + 1]);
    } else {
      return false;
    }
  }
  return argc % 2 == 1 && options.repetitions > 0;
}

size_t differingSamples(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  size_t differing = 0;
  for (size_t i = 0; i < a.size(); ++i) differing += std::memcmp(&a[i], &b[i], sizeof(Vec3)) != 0;
  return differing;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse(argc, argv, options)) {
    std::fprintf(stderr, "usage: %s [--levels 16,32,64] [--repetitions R] [--models a,b]\n",
                 argv[0]);
    return 2;
  }
  const cuda::CudaDeviceInfo device = cuda::queryCudaDevice();
  std::printf("device: %s\n", device.summary().c_str());
  if (!device.available) return 1;
  std::printf(
      "CPU: %d TBB threads; CPU times are medians of 5 calls, GPU kernel times means of "
      "%d launches after a warm-up\n\n",
      tbb::info::default_concurrency(), options.repetitions);
  std::printf(
      "| model | p | pieces | samples | CPU plan ms | CPU eval ms | GPU upload ms | "
      "GPU eval ms | GPU GB/s | CPU eval / GPU eval | equal |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  bool allEqual = true;
  for (const std::string& name : options.models) {
    const PatchSet patches = buildPatchSet(readObjFile(testing::modelsDir() + "/" + name + ".obj"));
    for (int p : options.levels) {
      UniformGrid grid;
      const double planMs = medianMs(5, [&] { planUniformGrid(patches, p, grid); });
      std::vector<Vec3> cpu(grid.samples());
      const double evalMs = medianMs(5, [&] { evaluateUniformGrid(patches, grid, cpu.data()); });

      const Clock::time_point uploadStart = Clock::now();
      cuda::CudaUniformGrid gpu(patches, grid);
      const double uploadMs = msSince(uploadStart);
      gpu.launch();
      const size_t differing = differingSamples(gpu.download(), cpu);
      allEqual = allEqual && differing == 0;
      const double kernelMs = gpu.timeKernelMs(options.repetitions);
      const double gigabytes = double(grid.samples()) * sizeof(Vec3) / 1e9;
      std::printf("| %s | %d | %zu | %zu | %.2f | %.2f | %.2f | %.3f | %.0f | %.1f | %s |\n",
                  name.c_str(), p, grid.pieces.size(), grid.samples(), planMs, evalMs, uploadMs,
                  kernelMs, gigabytes / (kernelMs / 1e3), evalMs / kernelMs,
                  differing == 0 ? "bit for bit" : (std::to_string(differing) + " differ").c_str());
      std::fflush(stdout);
    }
  }
  return allEqual ? 0 : 1;
}
