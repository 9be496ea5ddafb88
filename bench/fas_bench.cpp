// Table 1 of the paper (§4.3) on this machine's CPU: 100K rings of valence n refined to depth d,
// every level's 12n+1 refined points written to memory, by CER-based FAS (core/rings/fas.h) and by
// OpenSubdiv's stencil tables (osd_ring_stencils.h), next to the memory write floor
// (write_floor.h). Run `tessera-bench --benchmark_filter=BM_Fas`; bench/RESULTS.md has the numbers.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "bench/machine_load.h"
#include "bench/osd_ring_stencils.h"
#include "bench/ring_workload.h"
#include "bench/touched_buffer.h"
#include "bench/write_floor.h"
#include "core/rings/fas.h"

namespace tessera::bench {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kValences[] = {3, 5, 6, 7, 8, 9, 10};
constexpr int kDepths[] = {4, 5, 6};
constexpr int kThreads = 2;  // this machine's cores; TBB (FAS) uses all of them by default
constexpr double kOsdTolerance = 1e-5;  // relative to the ring's extent

// How OpenSubdiv is driven: rings per EvalStencils call, and whether the stencils are reordered
// so that OpenMP's static split gives both threads the same work (balanceForStaticSchedule).
struct OsdConfig {
  int chunkRings;
  bool balanced;
};
// Chosen with BM_OsdChunkSweep on this machine (bench/RESULTS.md).
constexpr OsdConfig kOsdConfig{16384, true};

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string caseKey(const char* kind, int n, int depth, OsdConfig osd = {0, false}) {
  return std::string(kind) + "/" + std::to_string(n) + "/" + std::to_string(depth) + "/" +
         std::to_string(osd.chunkRings) + (osd.balanced ? "/balanced" : "");
}

// Counters every Table 1 case reports; `seconds` is the total over all iterations. The floor is
// measured on the case's own output buffer right after its iterations (write_floor.h), and the
// process-wide best bandwidth gives a second, lower floor (floor_best_ms).
void reportWriteCounters(benchmark::State& state, float* output, size_t bytes, double seconds) {
  const double perIteration = seconds / double(state.iterations());
  const double floorSeconds = bufferWriteFloorSeconds(output, bytes / sizeof(float), kThreads);
  state.counters["rings"] = kTableRings;
  state.counters["bytes_written"] = double(bytes);
  state.counters["GB/s"] = double(bytes) / perIteration / 1e9;
  state.counters["floor_ms"] = floorSeconds * 1e3;
  state.counters["floor_best_ms"] = double(bytes) / bestWriteBandwidth() * 1e3;
  state.counters["x_floor"] = perIteration / floorSeconds;
}

// Times `work` per iteration with the wall clock: the work runs on every core, so the calling
// thread's CPU time says nothing.
// Also reports others_cpu (machine_load.h): results taken while it is high are not clean; and
// best_ms, the fastest single iteration, the one least disturbed on a shared machine.
template <class Work>
double timeIterations(benchmark::State& state, Work work) {
  double total = 0, best = 1e30;
  const CpuSample before = sampleCpu();
  for (auto _ : state) {
    auto start = Clock::now();
    double seconds;
    if constexpr (std::is_same_v<decltype(work()), double>) {
      seconds = work();  // the work timed itself (e.g. without thread start-up)
    } else {
      work();
      seconds = secondsSince(start);
    }
    state.SetIterationTime(seconds);
    total += seconds;
    best = std::min(best, seconds);
  }
  state.counters["others_cpu"] = othersShare(before, sampleCpu());
  state.counters["best_ms"] = best * 1e3;
  return total;
}

// ---- CER-based FAS -------------------------------------------------------------------------

struct CerCase : CaseState {
  RingRules rules;
  int blockCount = 0;
  std::unique_ptr<TouchedBuffer<float>> blocks;  // packed input, same kind of pages as the output
  std::unique_ptr<TouchedBuffer<float>> output;
};

std::unique_ptr<CaseState> prepareCer(const cer::RingShape& shape, int depth) {
  auto c = std::make_unique<CerCase>();
  c->rules = makeRingRules(shape, nullptr, false);
  std::vector<float> packed;
  {
    std::vector<float> rings = tiledRings(shape, distinctRings(shape), kTableRings);
    packed = packRingBlocks(shape, rings.data(), kTableRings);
  }
  c->blockCount = int(packed.size() / ringBlockFloats(shape));
  c->blocks = std::make_unique<TouchedBuffer<float>>(packed.size());
  std::memcpy(c->blocks->data(), packed.data(), packed.size() * sizeof(float));
  c->output =
      std::make_unique<TouchedBuffer<float>>(size_t(c->blockCount) * depth * refinedBlockFloats(shape));
  return c;
}

void BM_Fas_Cer(benchmark::State& state) {
  const int n = int(state.range(0)), depth = int(state.range(1));
  const cer::RingShape shape{n, false};
  bestWriteBandwidth();  // calibrate before any case buffer exists, if no floor benchmark ran
  auto& c =
      preparedCase<CerCase>(caseKey("cer", n, depth), [&] { return prepareCer(shape, depth); });
  double seconds = timeIterations(state, [&] {
    refineRingBlocks(c.rules, c.blocks->data(), c.blockCount, depth, c.output->data());
  });
  benchmark::DoNotOptimize(c.output->data());
  reportWriteCounters(state, c.output->data(), refinedBytes(shape, depth, c.blockCount * kFasLanes),
                      seconds);
}

// BM_Fas_Cer with the kernel chosen (argument 3: 0 AVX2, 1 AVX-512): the measurement behind
// fastestFasKernel(). Run with --benchmark_filter=BM_CerKernel.
void BM_CerKernel(benchmark::State& state) {
  const int n = int(state.range(0)), depth = int(state.range(1));
  const FasKernel kernel = state.range(2) != 0 ? FasKernel::kAvx512 : FasKernel::kAvx2;
  if (!fasKernelAvailable(kernel)) {
    state.SkipWithError("this CPU lacks the kernel's instruction set");
    return;
  }
  const cer::RingShape shape{n, false};
  bestWriteBandwidth();
  auto& c =
      preparedCase<CerCase>(caseKey("cer", n, depth), [&] { return prepareCer(shape, depth); });
  double seconds = timeIterations(state, [&] {
    refineRingBlocks(c.rules, c.blocks->data(), c.blockCount, depth, c.output->data(), kernel);
  });
  benchmark::DoNotOptimize(c.output->data());
  reportWriteCounters(state, c.output->data(), refinedBytes(shape, depth, c.blockCount * kFasLanes),
                      seconds);
}

// ---- OpenSubdiv stencil tables ---------------------------------------------------------------

struct OsdCase : CaseState {
  RingStencils stencils;
  std::unique_ptr<TouchedBuffer<float>> source, result;
  std::string error;  // non-empty: OSD disagrees with FAS, the case is skipped
};

// Compares OSD's result for a few rings (chunk starts and ends included) with CER FAS.
std::string verifyAgainstFas(const cer::RingShape& shape, int depth,
                             const std::vector<float>& distinct, const OsdCase& c, int chunkRings) {
  const RingRules rules = makeRingRules(shape, nullptr, false);
  std::vector<float> blocks = packRingBlocks(shape, distinct.data(), kDistinctRings);
  const int blockCount = int(blocks.size() / ringBlockFloats(shape));
  const size_t levelFloats = refinedBlockFloats(shape);
  std::vector<float> fas(size_t(blockCount) * depth * levelFloats);
  refineRingBlocks(rules, blocks.data(), blockCount, depth, fas.data());

  const int refined = shape.refinedPointCount(), points = shape.ringPointCount();
  const int stencilCount = c.stencils.count();
  std::vector<int> stencilOf(stencilCount);
  for (int s = 0; s < stencilCount; ++s) stencilOf[c.stencils.refinedPoint[s]] = s;
  for (int ring : {0, 1, chunkRings - 1, chunkRings, kTableRings / 2 + 3, kTableRings - 1}) {
    const int k = ring % kDistinctRings, block = k / kFasLanes, lane = k % kFasLanes;
    double extent = 1.0;
    for (int i = 0; i < 3 * points; ++i) {
      extent = std::max(extent, double(std::fabs(distinct[k * 3 * points + i])));
    }
    for (int level = 0; level < depth; ++level) {
      for (int p = 0; p < refined; ++p) {
        const float* mine =
            fas.data() + (size_t(block) * depth + level) * levelFloats + p * kFasBlockFloats;
        const float* osd = c.result->data() + chunkedIndex(stencilCount, kTableRings, chunkRings,
                                                           ring, stencilOf[level * refined + p]);
        for (int axis = 0; axis < 3; ++axis) {
          if (std::fabs(double(mine[axis * kFasLanes + lane]) - osd[axis]) >
              kOsdTolerance * extent) {
            return "OSD differs from FAS at ring " + std::to_string(ring) + " level " +
                   std::to_string(level + 1) + " point " + std::to_string(p);
          }
        }
      }
    }
  }
  return {};
}

std::unique_ptr<CaseState> prepareOsd(const cer::RingShape& shape, int depth, OsdConfig osd) {
  auto c = std::make_unique<OsdCase>();
  const std::vector<float> distinct = distinctRings(shape);
  c->stencils = buildRingStencils(distinctRingMesh(shape, 0), shape, depth);
  if (osd.balanced) c->stencils = balanceForStaticSchedule(c->stencils, kThreads);
  c->source = std::make_unique<TouchedBuffer<float>>(size_t(kTableRings) * shape.ringPointCount() * 3);
  fillChunkedRings(shape, distinct, kTableRings, osd.chunkRings, c->source->data());
  c->result = std::make_unique<TouchedBuffer<float>>(size_t(kTableRings) * c->stencils.count() * 3);
  omp_set_num_threads(kThreads);
  evalChunkedStencils(c->stencils, c->source->data(), c->result->data(), kTableRings,
                      osd.chunkRings);
  c->error = verifyAgainstFas(shape, depth, distinct, *c, osd.chunkRings);
  return c;
}

void runOsd(benchmark::State& state, int n, int depth, OsdConfig osd) {
  const cer::RingShape shape{n, false};
  bestWriteBandwidth();
  OsdCase* c = nullptr;
  try {
    c = &preparedCase<OsdCase>(caseKey("osd", n, depth, osd),
                               [&] { return prepareOsd(shape, depth, osd); });
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  if (!c->error.empty()) {
    state.SkipWithError(c->error.c_str());
    return;
  }
  omp_set_num_threads(kThreads);
  double seconds = timeIterations(state, [&] {
    evalChunkedStencils(c->stencils, c->source->data(), c->result->data(), kTableRings,
                        osd.chunkRings);
  });
  benchmark::DoNotOptimize(c->result->data());
  reportWriteCounters(state, c->result->data(), refinedBytes(shape, depth, kTableRings), seconds);
  state.counters["chunk_rings"] = osd.chunkRings;
  state.counters["balanced"] = osd.balanced;
  state.counters["weights_per_ring"] = double(c->stencils.indices.size());
}

void BM_Fas_OsdStencil(benchmark::State& state) {
  runOsd(state, int(state.range(0)), int(state.range(1)), kOsdConfig);
}

// BM_Fas_OsdStencil with the chunk size and the stencil order as arguments 3 and 4 (1: balanced):
// how kOsdConfig was chosen. Run with --benchmark_filter=BM_OsdChunkSweep.
void BM_OsdChunkSweep(benchmark::State& state) {
  runOsd(state, int(state.range(0)), int(state.range(1)),
         {int(state.range(2)), state.range(3) != 0});
}

void BM_Fas_OsdStencilBuild(benchmark::State& state) {
  const int n = int(state.range(0)), depth = int(state.range(1));
  const cer::RingShape shape{n, false};
  const ControlMesh mesh = distinctRingMesh(shape, 0);
  size_t weights = 0;
  for (auto _ : state) {
    RingStencils stencils = buildRingStencils(mesh, shape, depth);
    weights = stencils.weights.size();
    benchmark::DoNotOptimize(stencils.weights.data());
  }
  state.counters["weights_per_ring"] = double(weights);
}

// ---- Memory write floor ----------------------------------------------------------------------

struct FloorCase : CaseState {
  TouchedBuffer<float> buffer{kFloorBufferBytes / sizeof(float)};
};

void BM_WriteFloor(benchmark::State& state, WriteMethod method, int threads) {
  auto& c = preparedCase<FloorCase>("floor", [] { return std::make_unique<FloorCase>(); });
  double best = 0;
  int pass = 0;
  double total = timeIterations(state, [&] {
    double seconds =
        timedWrite(method, c.buffer.data(), c.buffer.size(), threads, nonZeroFill(pass++));
    best = std::max(best, double(c.buffer.bytes()) / seconds);
    return seconds;
  });
  // The floor is what the whole machine can write, so only the all-core runs define it.
  if (threads == kThreads) recordWriteBandwidth(best);
  state.counters["GB/s"] = double(c.buffer.bytes()) * double(state.iterations()) / total / 1e9;
  state.counters["best_GB/s"] = best / 1e9;
}

// With --benchmark_repetitions the fastest repetition is reported too: on a shared machine it
// is the one least disturbed by other processes (RESULTS.md gives median and min).
double fastest(const std::vector<double>& values) {
  return *std::min_element(values.begin(), values.end());
}

void registerBenchmarks() {
  for (WriteMethod method :
       {WriteMethod::kStreamAvx2, WriteMethod::kStreamAvx512, WriteMethod::kMemset}) {
    if (!writeMethodAvailable(method)) continue;
    for (int threads : {1, kThreads}) {
      std::string name =
          "BM_WriteFloor/" + writeMethodName(method) + "/threads:" + std::to_string(threads);
      benchmark::RegisterBenchmark(name.c_str(), BM_WriteFloor, method, threads)
          ->UseManualTime()
          ->ComputeStatistics("min", fastest)
          ->Unit(benchmark::kMillisecond);
    }
  }
  // One (valence, depth) case after the other, so a case's buffers are prepared once for all
  // the methods that share them and freed before the next case.
  for (int n : kValences) {
    for (int depth : kDepths) {
      benchmark::RegisterBenchmark("BM_Fas_Cer", BM_Fas_Cer)
          ->Args({n, depth})
          ->UseManualTime()
          ->ComputeStatistics("min", fastest)
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark("BM_CerKernel", BM_CerKernel)
          ->Args({n, depth, 0})
          ->Args({n, depth, 1})
          ->UseManualTime()
          ->ComputeStatistics("min", fastest)
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark("BM_Fas_OsdStencil", BM_Fas_OsdStencil)
          ->Args({n, depth})
          ->UseManualTime()
          ->ComputeStatistics("min", fastest)
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark("BM_Fas_OsdStencilBuild", BM_Fas_OsdStencilBuild)
          ->Args({n, depth})
          ->UseRealTime()
          ->ComputeStatistics("min", fastest)
          ->Unit(benchmark::kMillisecond);
    }
  }
  auto* sweep = benchmark::RegisterBenchmark("BM_OsdChunkSweep", BM_OsdChunkSweep);
  for (int n : {3, 6, 10}) {
    for (int depth : {4, 6}) {
      for (int balanced : {0, 1}) {
        for (int rings = 64; rings <= 16384; rings *= 4) sweep->Args({n, depth, rings, balanced});
      }
    }
  }
  sweep->UseManualTime()->ComputeStatistics("min", fastest)->Unit(benchmark::kMillisecond);
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  using namespace tessera::bench;
  omp_set_num_threads(kThreads);
  registerBenchmarks();
  benchmark::AddCustomContext("table_rings", std::to_string(kTableRings));
  benchmark::AddCustomContext("distinct_rings", std::to_string(kDistinctRings));
  benchmark::AddCustomContext("fas_lanes", std::to_string(tessera::kFasLanes));
  benchmark::AddCustomContext("osd_chunk_rings", std::to_string(kOsdConfig.chunkRings));
  benchmark::AddCustomContext("osd_balanced", kOsdConfig.balanced ? "true" : "false");
  benchmark::AddCustomContext("threads", std::to_string(kThreads));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
