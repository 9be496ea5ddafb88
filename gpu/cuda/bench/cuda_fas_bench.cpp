// tessera-cuda-bench: the paper's Table 1 (§4.3) on a CUDA device: 100K extraordinary rings of
// one valence refined to depth 4, 5 and 6, every level's 12n+1 points written to device memory.
// Rings are uploaded once; each case times only the kernels, with CUDA events, as the mean of
// several launches after a warm-up launch. Before timing, a sample of rings is checked against
// the CPU path (core/rings/fas.h refineRing) so that a wrong kernel cannot report a fast time. The
// baseline beside it, in the same process: the CPU's refineRingBlocks on the same rings (all
// cores, packed and output buffer prepared untimed), median of 5 calls after a warm-up.
//
// Usage: tessera-cuda-bench [--rings N] [--repetitions R] [--valences 3,5,6] [--depths 4,5,6]
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/rings/fas.h"
#include "gpu/cuda/cuda_fas.h"
#include "gpu/cuda/device_info.h"
#include "reference/ring_meshes.h"

namespace {

using namespace tessera;

struct Options {
  int rings = 100'000;
  int repetitions = 20;
  std::vector<int> valences = {3, 5, 6, 7, 8, 9, 10};  // Table 1 has no valence 4
  std::vector<int> depths = {4, 5, 6};
};

std::vector<int> parseList(const char* text) {
  std::vector<int> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) values.push_back(std::atoi(item.c_str()));
  return values;
}

bool parse(int argc, char** argv, Options& options) {
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--rings")) {
      options.rings = std::atoi(argv[i + 1]);
    } else if (!std::strcmp(argv[i], "--repetitions")) {
      options.repetitions = std::atoi(argv[i + 1]);
    } else if (!std::strcmp(argv[i], "--valences")) {
      options.valences = parseList(argv[i + 1]);
    } else if (!std::strcmp(argv[i], "--depths")) {
      options.depths = parseList(argv[i + 1]);
    } else {
      return false;
    }
  }
  return argc % 2 == 1 && options.rings > 0 && options.repetitions > 0;
}

// 64 distinct jittered rings tiled to `count`, so every ring is read from device memory.
constexpr int kDistinct = 64;

std::vector<float> distinctRings(const cer::RingShape& shape) {
  std::vector<float> rings;
  for (int k = 0; k < kDistinct; ++k) {
    ControlMesh mesh = testing::makeRingMesh(shape, 1000 + k);
    for (const Vec3& p : mesh.positions) rings.insert(rings.end(), {p.x, p.y, p.z});
  }
  return rings;
}

std::vector<float> tiled(const std::vector<float>& distinct, size_t ringFloats, int count) {
  std::vector<float> rings(size_t(count) * ringFloats);
  for (int r = 0; r < count; ++r) {
    std::memcpy(&rings[r * ringFloats], &distinct[(r % kDistinct) * ringFloats],
                ringFloats * sizeof(float));
  }
  return rings;
}

// Largest |GPU - CPU| over the first kDistinct rings, relative to the largest coordinate.
double checkAgainstCpu(const RingRules& rules, int depth, const std::vector<float>& distinct,
                       const std::vector<float>& gpu) {
  const size_t ringFloats = size_t(rules.shape.ringPointCount()) * 3;
  const size_t perRing = size_t(depth) * rules.shape.refinedPointCount() * 3;
  double worst = 0, extent = 0;
  for (int k = 0; k < kDistinct; ++k) {
    std::vector<float> cpu = refineRing(rules, &distinct[k * ringFloats], depth);
    for (size_t f = 0; f < perRing; ++f) {
      double difference = std::fabs(double(gpu[k * perRing + f]) - double(cpu[f]));
      worst = std::isfinite(difference) ? std::max(worst, difference) : INFINITY;
      extent = std::max(extent, double(std::fabs(cpu[f])));
    }
  }
  return extent > 0 ? worst / extent : worst;
}

// Median wall-clock ms of refineRingBlocks over the same rings, everything prepared untimed.
double cpuMedianMs(const RingRules& rules, int depth, const std::vector<float>& rings, int count) {
  const std::vector<float> blocks = packRingBlocks(rules.shape, rings.data(), count);
  const int blockCount = (count + kFasLanes - 1) / kFasLanes;
  const size_t outputFloats = size_t(blockCount) * size_t(depth) * refinedBlockFloats(rules.shape);
  std::unique_ptr<float[], decltype(&std::free)> output(
      static_cast<float*>(std::aligned_alloc(64, (outputFloats * sizeof(float) + 63) / 64 * 64)),
      &std::free);
  std::fill_n(output.get(), outputFloats, 0.0f);
  std::vector<double> times;
  for (int run = 0; run < 6; ++run) {
    const auto start = std::chrono::steady_clock::now();
    refineRingBlocks(rules, blocks.data(), blockCount, depth, output.get());
    const auto stop = std::chrono::steady_clock::now();
    if (run > 0) times.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
  }
  std::nth_element(times.begin(), times.begin() + 2, times.end());
  return times[2];
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse(argc, argv, options)) {
    std::fprintf(stderr,
                 "usage: %s [--rings N] [--repetitions R] [--valences 3,5] [--depths 4,5,6]\n",
                 argv[0]);
    return 2;
  }
  const cuda::CudaDeviceInfo device = cuda::queryCudaDevice();
  std::printf("device: %s\n", device.summary().c_str());
  if (!device.available) return 1;
  std::printf("%d rings per case, mean of %d launches after one warm-up; kernel time only. "
              "CPU: refineRingBlocks, %d TBB threads, median of 5\n\n",
              options.rings, options.repetitions, tbb::info::default_concurrency());
  std::printf("%7s %5s %10s %12s %10s %8s %6s %12s %10s %8s\n", "valence", "depth", "ms",
              "GB written", "GB/s", "blocks", "warps", "max rel err", "CPU ms", "CPU/GPU");
  bool allExact = true, allWithinTolerance = true;
  for (int depth : options.depths) {
    for (int n : options.valences) {
      const cer::RingShape shape{n, false};
      const RingRules rules = makeRingRules(shape, nullptr, false);
      const std::vector<float> distinct = distinctRings(shape);
      const std::vector<float> rings =
          tiled(distinct, size_t(shape.ringPointCount()) * 3, options.rings);
      cuda::CudaFasBatch batch(rules, depth, options.rings, rings.data());
      batch.launch();
      const double error = checkAgainstCpu(rules, depth, distinct, batch.download());
      allExact = allExact && error == 0.0;
      allWithinTolerance = allWithinTolerance && error <= 1e-6;
      const float milliseconds = batch.timeKernelMs(options.repetitions);
      const double gigabytes = double(batch.outputFloats()) * sizeof(float) / 1e9;
      const double cpuMs = cpuMedianMs(rules, depth, rings, options.rings);
      std::printf("%7d %5d %10.3f %12.3f %10.1f %8d %6d %12.2e %10.2f %8.1f\n", n, depth,
                  milliseconds, gigabytes, gigabytes / (milliseconds / 1e3), batch.blocks(),
                  batch.warpsPerBlock(), error, cpuMs, cpuMs / milliseconds);
    }
  }
  std::printf("\nGPU output %s the CPU path on the checked rings\n",
              allExact ? "equals (bit for bit)" : "differs from");
  return allWithinTolerance ? 0 : 1;
}
