// The user's job, side by side with OpenSubdiv at the oracle uniform rate (docs/ADAPTIVE.md):
//
//   BM_TessGlb_Tessera/<model>/<eps>         tessellate() to a relative tolerance (the adaptive
//       path: plan, stitch, evaluate, triangulate) and writeGlb(), the patch set built in setup
//       (the server caches it). Counters: triangles, the oracle's, their ratio, the proven bound
//       and (once per case, not timed) the measured two-sided distance, over ε.
//   BM_TessGlb_OsdBfrOracle/<model>/<eps>    OpenSubdiv Bfr at the oracle rate for that case
//       (bench/oracle_rates.csv, tools/oracle_rates) by bench/bfr_oracle.h: per face, on all
//       cores, what Bfr's tutorials do with a factory whose cache persists between iterations
//       (InitVertexSurface, PreparePatchPoints, Tessellation at a uniform rate, GetCoords,
//       Evaluate with derivatives for the normals, GetFacets), into buffers allocated and touched
//       in setup. Faces keep their own copies of edge points (no watertight assembly), which only
//       favours Bfr.
//   BM_TessGlb_Paired/<model>/<eps>          the two above alternated in blocks (each side
//       called again for at least 25 ms, then the other), so that both see the same state of
//       the machine: on a shared VM whose speed drifts by up to 2x over minutes, the separate
//       benchmarks' medians (taken seconds apart) move against each other, while the median of
//       per-block ratios stays put. Blocks keep each side's caches as warm as in its own
//       benchmark (one call of each in turn made Tessera ~30 % slower on the torus at 1e-3, its
//       patch set evicted by Bfr's run). Counters: tessera_ms, bfr_ms (medians of the blocks'
//       means) and time_ratio (the median of the blocks' Tessera / Bfr).
//
// bench/adaptive_table.py turns the JSON into bench/ADAPTIVE-RESULTS.md (ratios per case and
// summed); that file has the commands.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include "bench/bfr_oracle.h"
#include "bench/machine_load.h"
#include "bench/oracle_rate.h"
#include "bench/tess_common.h"
#include "core/output/glb_writer.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
#include "reference/limit_distance.h"

namespace tessera::bench {
namespace {

struct Model {
  ControlMesh mesh;
  PatchSet patches;
  std::vector<float> points;  // xyz per control vertex, for Bfr
};

const Model& model(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Model>> models;
  auto& entry = models[name];
  if (!entry) {
    entry = std::make_unique<Model>();
    entry->mesh = geometryMesh(name);
    entry->patches = buildPatchSet(entry->mesh);
    for (const Vec3& p : entry->mesh.positions) entry->points.insert(entry->points.end(), {p.x, p.y, p.z});
  }
  return *entry;
}

// The measured two-sided distance of Tessera's mesh over ε, once per case (not timed); set
// TESSERA_BENCH_SKIP_MEASURE to leave it out.
double measuredOverEps(const Model& m, const std::string& name, double eps) {
  static std::map<std::string, double> measured;
  const std::string key = name + "/" + std::to_string(eps);
  if (std::getenv("TESSERA_BENCH_SKIP_MEASURE")) return -1;
  auto found = measured.find(key);
  if (found != measured.end()) return found->second;
  TessellationOptions options = adaptiveOptions(eps);
  options.recordParameters = true;
  const TessellationResult result = tessellate(m.patches, m.mesh, options);
  static std::map<std::string, std::unique_ptr<testing::LimitSurface>> surfaces;
  auto& surface = surfaces[name];
  if (!surface) surface = std::make_unique<testing::LimitSurface>(m.mesh);
  const testing::LimitDistanceReport report = testing::measureLimitDistance(*surface, testing::viewOf(result.mesh));
  return measured[key] = report.twoSidedRelative() / eps;
}

void tesseraGlb(benchmark::State& state, const std::string& name, double eps) {
  const Model& m = model(name);
  const TessellationOptions options = adaptiveOptions(eps);
  int64_t triangles = 0;
  double bound = 0, tolerance = 1;
  size_t bytes = 0;
  const double roundTrip = coreRoundTripNs();
  const CpuSample before = sampleCpu();
  for (auto _ : state) {
    TessellationResult result = tessellate(m.patches, m.mesh, options);
    std::vector<uint8_t> glb = writeGlb(result.mesh, {.description = {.sourceName = name}});
    triangles = result.summary.triangles;
    bound = result.summary.guaranteedBound, tolerance = result.summary.tolerance;
    bytes = glb.size();
    benchmark::DoNotOptimize(glb.data());
  }
  state.counters["others_cpu"] = othersShare(before, sampleCpu());
  state.counters["core_round_trip_ns"] = roundTrip;
  const OracleRate oracle = oracleRate(name, eps);
  state.counters["triangles"] = double(triangles);
  state.counters["oracle_triangles"] = double(oracle.triangles);
  state.counters["triangle_ratio"] = oracle.triangles > 0 ? double(triangles) / double(oracle.triangles) : 0;
  state.counters["oracle_beyond"] = oracle.beyond;
  state.counters["bound_over_eps"] = bound / tolerance;
  state.counters["measured_over_eps"] = measuredOverEps(m, name, eps);
  state.counters["glb_bytes"] = double(bytes);
}

void osdBfrOracle(benchmark::State& state, const std::string& name, double eps) {
  const OracleRate oracle = oracleRate(name, eps);
  if (oracle.rate <= 0) return state.SkipWithError("no oracle rate in bench/oracle_rates.csv");
  const Model& m = model(name);
  BfrOracle bfr(m.mesh, oracle.rate);
  const double roundTrip = coreRoundTripNs();
  const CpuSample before = sampleCpu();
  for (auto _ : state) bfr.run(m.points.data());
  state.counters["others_cpu"] = othersShare(before, sampleCpu());
  state.counters["core_round_trip_ns"] = roundTrip;
  state.counters["rate"] = oracle.rate;
  state.counters["oracle_beyond"] = oracle.beyond;
  state.counters["triangles"] = double(bfr.triangles());
  state.counters["measured_over_eps"] = oracle.measured / eps;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n == 0 ? 0 : n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Calls `call` again until at least `least` ms have passed; the mean time of one call.
template <typename Call>
double blockMean(double least, Call call) {
  const auto start = std::chrono::steady_clock::now();
  int calls = 0;
  do {
    call();
    ++calls;
  } while (millisecondsSince(start) < least);
  return millisecondsSince(start) / calls;
}

void pairedGlb(benchmark::State& state, const std::string& name, double eps) {
  constexpr double kBlockMs = 25;
  const OracleRate oracle = oracleRate(name, eps);
  if (oracle.rate <= 0) return state.SkipWithError("no oracle rate in bench/oracle_rates.csv");
  const Model& m = model(name);
  const TessellationOptions options = adaptiveOptions(eps);
  BfrOracle bfr(m.mesh, oracle.rate);
  const double roundTripBefore = coreRoundTripNs();
  std::vector<double> tessera, osd, ratio;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    tessera.push_back(blockMean(kBlockMs, [&] {
      TessellationResult result = tessellate(m.patches, m.mesh, options);
      std::vector<uint8_t> glb = writeGlb(result.mesh, {.description = {.sourceName = name}});
      benchmark::DoNotOptimize(glb.data());
    }));
    osd.push_back(blockMean(kBlockMs, [&] { bfr.run(m.points.data()); }));
    ratio.push_back(tessera.back() / osd.back());
    state.SetIterationTime(millisecondsSince(start) * 1e-3);
  }
  state.counters["tessera_ms"] = median(tessera);
  state.counters["bfr_ms"] = median(osd);
  state.counters["time_ratio"] = median(ratio);
  // Before and after the blocks: the VM can change between its two placements meanwhile.
  state.counters["core_round_trip_ns"] = roundTripBefore;
  state.counters["core_round_trip_after_ns"] = coreRoundTripNs();
}

const bool registered = [] {
  for (const std::string& name : adaptiveModels()) {
    for (double eps : kAdaptiveTolerances) {
      char suffix[64];
      std::snprintf(suffix, sizeof suffix, "%s/%g", name.c_str(), eps);
      benchmark::RegisterBenchmark((std::string("BM_TessGlb_Tessera/") + suffix).c_str(), tesseraGlb, name, eps)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark((std::string("BM_TessGlb_OsdBfrOracle/") + suffix).c_str(), osdBfrOracle,
                                   name, eps)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark((std::string("BM_TessGlb_Paired/") + suffix).c_str(), pairedGlb, name, eps)
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime();
    }
  }
  return true;
}();

}  // namespace
}  // namespace tessera::bench
