// What the tessellation benchmarks (tess_bench.cpp: the paper's Table 2, Fig. 5, Fig. 6 and a
// tightness measurement) share: the paper's five models loaded once per process, wall-clock timing of multi-threaded work with the machine's load beside it,
// and the write-floor counters (write_floor.h).
#pragma once

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "bench/machine_load.h"
#include "bench/touched_buffer.h"
#include "core/mesh/control_mesh.h"
#include "core/request/tessellation_options.h"
#include "core/rings/patch_set.h"

namespace tessera::bench {

inline constexpr int kTessThreads = 2;  // this machine's cores (TBB and OpenMP use both)

// The paper's models (§6 "Models setting"), by file base name under the models folder.
inline const std::vector<std::string>& paperModels() {
  static const std::vector<std::string> names = {"bigguy", "monsterfrog", "armorguy", "t-rex", "car"};
  return names;
}

// TESSERA_MODELS_DIR if set, else ../shared/models beside the checkout this file was built from.
std::string tessModelsDir();

// The cases of the user's job against OpenSubdiv at the oracle rate (tess_glb_bench.cpp,
// cold_bench.cpp): the paper's five models and four OpenSubdiv shapes (n-gons, creases,
// semi-sharp creases), at relative tolerances 1e-2, 1e-3 and 1e-4.
const std::vector<std::string>& adaptiveModels();
inline constexpr double kAdaptiveTolerances[] = {1e-2, 1e-3, 1e-4};
// A relative tolerance ε, with a triangle budget no case comes near.
TessellationOptions adaptiveOptions(double eps);

// <models>/<name>.obj, or <models>/opensubdiv-shapes/<name>.obj for catmark_* (reference/models.h's
// folder).
std::string modelObjPath(const std::string& name);

// The model's control mesh, read once per process, geometry only: the baselines make positions
// and normals, and the models' own UVs would add their evaluation and seam copies to Tessera's
// side alone.
const ControlMesh& geometryMesh(const std::string& name);

struct LoadedModel {
  std::string name;
  ControlMesh mesh;
  PatchSet patches;  // buildPatchSet: preprocessing, never timed
  double diagonal = 0, minBoxSide = 0;
};

// Reads and preprocesses a model the first time it is asked for; kept for the whole run.
const LoadedModel& loadedModel(const std::string& name);

// Times `work` per iteration with the wall clock (the work runs on every core) and reports
// others_cpu: the share of the machine other processes took meanwhile (machine_load.h).
template <class Work>
double timeWallIterations(benchmark::State& state, Work work) {
  using Clock = std::chrono::steady_clock;
  double total = 0;
  const CpuSample before = sampleCpu();
  for (auto _ : state) {
    auto start = Clock::now();
    work();
    double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    state.SetIterationTime(seconds);
    total += seconds;
  }
  state.counters["others_cpu"] = othersShare(before, sampleCpu());
  return total;
}

// Measures the write floor before any case buffer exists: the best two-thread bandwidth over
// 20 passes of each store kind write_floor.h offers (recorded there for bestWriteBandwidth()).
void calibrateWriteFloor();

// samples, bytes_written (xyz floats), GB/s, floor_ms (those bytes at the machine's measured
// write bandwidth, write_floor.h) and x_floor (time / floor). `seconds`: total of all iterations.
void reportSampleCounters(benchmark::State& state, size_t samples, double seconds);

// One prepared case at a time (buffers of up to a few GB): asking for another key frees the
// previous case first. A single slot for every kind of case in this process.
struct TessCase {
  virtual ~TessCase() = default;
};

struct TessCaseSlot {
  std::string key;
  std::unique_ptr<TessCase> state;
};
TessCaseSlot& tessCaseSlot();

template <class State, class Make>
State& currentCase(const std::string& key, Make make) {
  TessCaseSlot& slot = tessCaseSlot();
  if (slot.key != key || !slot.state) {
    slot.state.reset();
    slot.key.clear();
    slot.state = make();
    slot.key = key;
  }
  return static_cast<State&>(*slot.state);
}

double fastestOf(const std::vector<double>& values);

}  // namespace tessera::bench
