// Issue 46's cold and edit jobs, side by side with OpenSubdiv at the oracle uniform rate in one
// process, each with the peak memory it takes (bench/COLD-RESULTS.md has the numbers and the
// commands):
//
//   BM_Cold_Tessera/<model>/<eps>       a control mesh already in memory (the OBJ read once,
//       outside any timing) to a GLB: buildPatchSet (preprocessing), tessellate() at relative
//       tolerance ε, writeGlb (float), and freeing it all. Nothing of the mesh survives an
//       iteration; what does is process-wide and the same for every mesh (core's scratch pools,
//       the depth tables, all checked in for the kinds these meshes have, TBB's threads).
//   BM_Cold_OsdBfrOracle/<model>/<eps>  the same mesh to Bfr at the oracle rate
//       (bench/oracle_rates.csv): Far::TopologyRefiner, a RefinerSurfaceFactory with an empty
//       cache and the output buffers made, then per face on both cores positions, normals and
//       facets (bench/bfr_oracle.h), and freeing it all. No GLB, which only favours Bfr.
//   BM_Edit_Tessera/<model>/<eps>       the same topology with every vertex moved
//       (bench/smooth_edit.h, another frame each iteration) to a GLB, with the rest mesh's
//       topology (core's MeshTopology: Far's refinement, the pieces' layout, the seams) made once
//       in setup, as the server's patch-set cache keeps it for an edited cage: each frame refines
//       and gathers its positions, builds its surface, tessellates and writes the GLB.
//   BM_Edit_OsdBfrOracle/<model>/<eps>  what OpenSubdiv users do for animation: the refiner, the
//       factory, each face's Surface and the facets made once in setup; per frame, patch points
//       from the new positions and evaluation (positions and normals) at the rest mesh's oracle
//       rate.
//
// Each job is timed alone (manual time): an edit's new positions are the user's, made before the
// clock starts. Counters: peak_mib, the process's resident high-water mark above its size before
// the benchmark made anything but its input, over setup and every iteration (bench/peak_memory.h);
// kept_mib, what setup keeps resident between iterations (and for the edit topology_charged_mib,
// what the server's cache charges for the kept topology); triangles; the stages' mean times
// (Tessera: preprocess_ms, of it topology_ms up to the end of the topology — validation, sheets,
// Far's refinement and the pieces' layout; nothing on the edit path,
// tessellate_ms, glb_ms, free_ms; Bfr: setup_ms for the refiner, the
// factory and the buffers (the edit's: once, with the surfaces and facets, untimed), evaluate_ms,
// free_ms); others_cpu and core_round_trip_ns as in
// tess_glb_bench.cpp. bench/cold_table.py turns the JSON into bench/COLD-RESULTS.md's tables.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "bench/bfr_oracle.h"
#include "bench/machine_load.h"
#include "bench/oracle_rate.h"
#include "bench/peak_memory.h"
#include "bench/smooth_edit.h"
#include "bench/tess_common.h"
#include "core/output/glb_writer.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"

namespace tessera::bench {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsBetween(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

// What Tessera keeps from a mesh's first frame for later frames that move only its positions: its
// topology (core/pipeline/preprocessing.h), made in setup (untimed, counted in kept_mib).
class TopologyReuse {
 public:
  explicit TopologyReuse(const ControlMesh& firstFrame) : topology_(buildMeshTopology(firstFrame)) {}
  PatchSet patchSet(const ControlMesh& moved, const PreprocessingOptions& options) const {
    return buildPatchSet(moved, *topology_, options);
  }
  // What the server's patch-set cache charges for it (MeshTopology::bytes), beside kept_mib.
  double chargedMiB() const { return double(topology_->bytes()) / (1 << 20); }

 private:
  std::shared_ptr<const MeshTopology> topology_;
};

// Sums of each stage's time over the iterations, and the last job's size.
struct TesseraStages {
  double preprocess = 0, tessellate = 0, glb = 0, release = 0;
  double refine = 0;  // of preprocess: up to the end of the topology (validation, sheets, Far, layout)
  int64_t triangles = 0;
  double boundOverEps = 0;
  size_t glbBytes = 0;
};

// A GLB from a mesh: the patch set from `makePatchSet(mesh, options)` (preprocessing), the
// adaptive tessellation and the float GLB, everything freed before returning. Preprocessing's
// afterRefining hook (which costs nothing; its last call is where the positions' part begins)
// splits its time at the end of the topology.
template <class MakePatchSet>
void tesseraGlb(const ControlMesh& mesh, const std::string& name,
                const TessellationOptions& options, MakePatchSet makePatchSet,
                TesseraStages& stages) {
  const Clock::time_point start = Clock::now();
  Clock::time_point refined = start, written;
  PreprocessingOptions preprocessing;
  preprocessing.afterRefining = [&refined](int64_t) { refined = Clock::now(); };
  // As the CLI and the server do: the surface for the request's tolerance (its chain depth).
  preprocessing.finestRelativeTolerance = finestRelativeTolerance(mesh, options);
  {
    const PatchSet patches = makePatchSet(mesh, preprocessing);
    const Clock::time_point preprocessed = Clock::now();
    const TessellationResult result = tessellate(patches, mesh, options);
    const Clock::time_point tessellated = Clock::now();
    const std::vector<uint8_t> glb = writeGlb(result.mesh, {.description = {.sourceName = name}});
    written = Clock::now();
    benchmark::DoNotOptimize(glb.data());
    stages.preprocess += millisecondsBetween(start, preprocessed);
    stages.refine += millisecondsBetween(start, refined);
    stages.tessellate += millisecondsBetween(preprocessed, tessellated);
    stages.glb += millisecondsBetween(tessellated, written);
    stages.triangles = result.summary.triangles;
    stages.boundOverEps = result.summary.guaranteedBound / result.summary.tolerance;
    stages.glbBytes = glb.size();
  }
  stages.release += millisecondsBetween(written, Clock::now());
}

struct BfrStages {
  double setup = 0, evaluate = 0, release = 0;
  size_t triangles = 0;
};

// xyz per control vertex, as Bfr reads them.
void copyPoints(const std::vector<Vec3>& positions, std::vector<float>& points) {
  points.resize(3 * positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    points[3 * i] = positions[i].x;
    points[3 * i + 1] = positions[i].y;
    points[3 * i + 2] = positions[i].z;
  }
}

// Runs every iteration as `frame(i)` (untimed: the input of iteration i, i = 1, 2, ...) and then
// `job()`, timed alone, with the memory high-water mark restarted just before the job and taken
// just after.
template <class Frame, class Job>
void timeJobs(benchmark::State& state, PeakMemory& memory, Frame frame, Job job) {
  const CpuSample before = sampleCpu();
  int64_t iteration = 0;
  for (auto _ : state) {
    frame(++iteration);
    memory.restart();
    const Clock::time_point start = Clock::now();
    job();
    state.SetIterationTime(millisecondsBetween(start, Clock::now()) * 1e-3);
    memory.record();
  }
  state.counters["others_cpu"] = othersShare(before, sampleCpu());
}

void reportMemory(benchmark::State& state, const PeakMemory& memory, double keptMiB) {
  state.counters["peak_mib"] = memory.peakMiB();
  state.counters["kept_mib"] = keptMiB;
  state.counters["peak_restart_ok"] = memory.restartWorks();
}

void reportTessera(benchmark::State& state, const TesseraStages& stages) {
  const double n = double(std::max<benchmark::IterationCount>(1, state.iterations()));
  state.counters["preprocess_ms"] = stages.preprocess / n;
  state.counters["topology_ms"] = stages.refine / n;
  state.counters["tessellate_ms"] = stages.tessellate / n;
  state.counters["glb_ms"] = stages.glb / n;
  state.counters["free_ms"] = stages.release / n;
  state.counters["triangles"] = double(stages.triangles);
  state.counters["bound_over_eps"] = stages.boundOverEps;
  state.counters["glb_bytes"] = double(stages.glbBytes);
}

void reportBfr(benchmark::State& state, const BfrStages& stages, const OracleRate& oracle) {
  const double n = double(std::max<benchmark::IterationCount>(1, state.iterations()));
  state.counters["setup_ms"] = stages.setup / n;
  state.counters["evaluate_ms"] = stages.evaluate / n;
  state.counters["free_ms"] = stages.release / n;
  state.counters["triangles"] = double(stages.triangles);
  state.counters["rate"] = oracle.rate;
  state.counters["oracle_beyond"] = oracle.beyond;
}

// Iterations of a cold job all take the same input.
void sameInput(int64_t /*iteration*/) {}

void coldTessera(benchmark::State& state, const std::string& name, double eps) {
  const ControlMesh& mesh = geometryMesh(name);
  const TessellationOptions options = adaptiveOptions(eps);
  state.counters["core_round_trip_ns"] = coreRoundTripNs();
  PeakMemory memory;
  TesseraStages stages;
  const auto fromScratch = [](const ControlMesh& m, const PreprocessingOptions& o) {
    return buildPatchSet(m, o);
  };
  timeJobs(state, memory, sameInput, [&] { tesseraGlb(mesh, name, options, fromScratch, stages); });
  reportMemory(state, memory, 0);
  reportTessera(state, stages);
}

// Bfr's whole job from a mesh: a new refiner, factory (empty cache) and output, the evaluation,
// everything freed before returning.
void bfrFromScratch(const ControlMesh& mesh, int rate, const std::vector<float>& points,
                    BfrStages& stages) {
  const Clock::time_point start = Clock::now();
  Clock::time_point evaluated;
  {
    BfrOracle bfr(mesh, rate);
    const Clock::time_point made = Clock::now();
    bfr.run(points.data());
    evaluated = Clock::now();
    stages.setup += millisecondsBetween(start, made);
    stages.evaluate += millisecondsBetween(made, evaluated);
    stages.triangles = bfr.triangles();
  }
  stages.release += millisecondsBetween(evaluated, Clock::now());
}

void coldBfr(benchmark::State& state, const std::string& name, double eps) {
  const OracleRate oracle = oracleRate(name, eps);
  if (oracle.rate <= 0) return state.SkipWithError("no oracle rate in bench/oracle_rates.csv");
  const ControlMesh& mesh = geometryMesh(name);
  std::vector<float> points;
  copyPoints(mesh.positions, points);
  state.counters["core_round_trip_ns"] = coreRoundTripNs();
  PeakMemory memory;
  BfrStages stages;
  timeJobs(state, memory, sameInput, [&] { bfrFromScratch(mesh, oracle.rate, points, stages); });
  reportMemory(state, memory, 0);
  reportBfr(state, stages, oracle);
}

void editTessera(benchmark::State& state, const std::string& name, double eps) {
  const ControlMesh& rest = geometryMesh(name);
  const TessellationOptions options = adaptiveOptions(eps);
  const SmoothEdit edit(rest);
  ControlMesh moved = rest;  // the frames' positions are written over this copy's
  state.counters["core_round_trip_ns"] = coreRoundTripNs();
  PeakMemory memory;
  const TopologyReuse reuse(rest);
  memory.record();
  const double kept = memory.residentMiB();
  TesseraStages stages;
  const auto nextFrame = [&](int64_t frame) { edit.apply(frame, moved.positions); };
  const auto reusing = [&](const ControlMesh& m, const PreprocessingOptions& o) {
    return reuse.patchSet(m, o);
  };
  timeJobs(state, memory, nextFrame, [&] { tesseraGlb(moved, name, options, reusing, stages); });
  reportMemory(state, memory, kept);
  state.counters["topology_charged_mib"] = reuse.chargedMiB();
  reportTessera(state, stages);
}

void editBfr(benchmark::State& state, const std::string& name, double eps) {
  const OracleRate oracle = oracleRate(name, eps);
  if (oracle.rate <= 0) return state.SkipWithError("no oracle rate in bench/oracle_rates.csv");
  const ControlMesh& rest = geometryMesh(name);
  const SmoothEdit edit(rest);
  std::vector<Vec3> moved;
  std::vector<float> points;
  edit.apply(0, moved);  // sized before the baseline: the frames' input is not the job's memory
  copyPoints(moved, points);
  state.counters["core_round_trip_ns"] = coreRoundTripNs();
  PeakMemory memory;
  BfrStages stages;
  const Clock::time_point start = Clock::now();
  BfrOracle bfr(rest, oracle.rate);
  bfr.prepareSurfaces();  // topology only: kept from frame to frame
  const double setupOnce = millisecondsBetween(start, Clock::now());
  memory.record();
  const double kept = memory.residentMiB();
  const auto nextFrame = [&](int64_t frame) {
    edit.apply(frame, moved);
    copyPoints(moved, points);
  };
  timeJobs(state, memory, nextFrame, [&] {
    const Clock::time_point frameStart = Clock::now();
    bfr.runPrepared(points.data());
    stages.evaluate += millisecondsBetween(frameStart, Clock::now());
  });
  stages.triangles = bfr.triangles();
  reportMemory(state, memory, kept);
  reportBfr(state, stages, oracle);
  state.counters["setup_ms"] = setupOnce;  // once, not per frame
}

const bool registered = [] {
  for (const std::string& name : adaptiveModels()) {
    for (double eps : kAdaptiveTolerances) {
      char suffix[64];
      std::snprintf(suffix, sizeof suffix, "%s/%g", name.c_str(), eps);
      const std::pair<const char*, void (*)(benchmark::State&, const std::string&, double)>
          kinds[] = {{"BM_Cold_Tessera/", coldTessera},
                     {"BM_Cold_OsdBfrOracle/", coldBfr},
                     {"BM_Edit_Tessera/", editTessera},
                     {"BM_Edit_OsdBfrOracle/", editBfr}};
      for (const auto& [prefix, run] : kinds) {
        benchmark::RegisterBenchmark((prefix + std::string(suffix)).c_str(), run, name, eps)
            ->Unit(benchmark::kMillisecond)
            ->UseManualTime();
      }
    }
  }
  return true;
}();

}  // namespace
}  // namespace tessera::bench
