// The paper's Table 2 (§6.1) on this machine's CPU: uniform tessellation level p ∈ {16, 32, 64}
// on the paper's five models, everything prior to rasterization, by Tessera and by OpenSubdiv,
// next to the memory write floor (write_floor.h). Also registers, from tess_figures.cpp, Fig. 6
// (depth estimation), Fig. 5 (η sweep) and the tightness measurement.
//
//   BM_TessUniform_Tessera/<model>/<p>       planUniformGrid (rings refined by FAS to ⌈log₂ p⌉ −
//       their Far level, levels max(p/2^d, 1)) into a grid kept from frame to frame, then
//       evaluateUniformGrid (AVX2) into a buffer allocated and touched in setup.
//   BM_TessUniform_OsdBfr/<model>/<p>        Bfr, surfaces and (u,v) prepared in setup (tess_osd.h)
//   BM_TessUniform_OsdBfrPerFace/<model>/<p> Bfr doing all its per-face work in the timed region
//   BM_TessUniform_OsdEval/<model>/<p>       Far::PatchTable (Gregory end caps) + OmpEvaluator
//
// Run `tessera-bench --benchmark_filter='BM_Tess|BM_Depth|BM_Tightness'`; bench/TESS-RESULTS.md
// has the numbers and the exact commands.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <memory>
#include <string>

#include "bench/tess_common.h"
#include "bench/tess_figures.h"
#include "bench/tess_osd.h"
#include "bench/write_floor.h"
#include "core/uniform/tessellation_plan.h"
#include "core/uniform/uniform_grid.h"

namespace tessera::bench {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kUniformLevels[] = {16, 32, 64};
constexpr int kBfrCheckFaceStride = 7;  // OsdEval is compared with Bfr on every 7th face

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Everything one (model, p) case needs, built lazily by whichever method asks first and kept
// while the four methods of that case run.
struct UniformCase : TessCase {
  const LoadedModel* model = nullptr;
  int level = 0;
  // Tessera: the grid is kept from frame to frame, as a viewer would keep it
  UniformGrid grid;
  size_t tessSamples = 0, pieces = 0;
  std::unique_ptr<TouchedBuffer<Vec3>> tessOut;
  double tessError = -1;  // max distance of checked samples to the limit surface / diagonal
  double tessInnermostError = -1;  // the same over innermost (approximated) pieces only
  // OpenSubdiv
  std::unique_ptr<OsdUniformSamples> osd;
  std::unique_ptr<TouchedBuffer<float>> osdOut;
  bool bfrPrepared = false, evalPrepared = false;
  double stencilMs = 0, evalVsBfr = -1, bfrError = -1;
  std::string error;
};

UniformCase& uniformCase(const std::string& name, int p) {
  return currentCase<UniformCase>(name + "/" + std::to_string(p), [&] {
    auto c = std::make_unique<UniformCase>();
    c->model = &loadedModel(name);
    c->level = p;
    return c;
  });
}

// The samples are checked against the limit surface through the domains of planTessellation's
// uniform pieces, which must be the grid's pieces in the same order.
void prepareTessera(UniformCase& c) {
  if (c.tessOut) return;
  const PatchSet& patches = c.model->patches;
  planUniformGrid(patches, c.level, c.grid);
  c.tessSamples = c.grid.samples();
  c.pieces = c.grid.pieces.size();
  c.tessOut = std::make_unique<TouchedBuffer<Vec3>>(c.tessSamples);
  evaluateUniformGrid(patches, c.grid, c.tessOut->data());
  TessellationOptions options;
  options.accuracy = Accuracy::uniformLevel(c.level);
  const TessellationPlan plan = planTessellation(patches, options);
  bool samePieces = plan.pieces.size() == c.pieces;
  for (size_t q = 0; samePieces && q < c.pieces; ++q)
    samePieces = plan.pieces[q].level == c.grid.pieces[q].level;
  if (!samePieces) throw std::runtime_error("the grid's pieces are not the plan's");
  c.tessError = sampledLimitDeviation(*c.model, plan, c.grid.offsets, c.tessOut->data(),
                                      c.tessInnermostError);
}

void BM_TessUniform_Tessera(benchmark::State& state, std::string name, int p) {
  calibrateWriteFloor();  // before any large buffer exists
  UniformCase* c = nullptr;
  try {
    c = &uniformCase(name, p);
    prepareTessera(*c);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  double planMs = 0, evalMs = 0;
  bool sizesMatch = true;
  double seconds = timeWallIterations(state, [&] {
    auto start = Clock::now();
    planUniformGrid(c->model->patches, p, c->grid);
    auto planned = Clock::now();
    sizesMatch = sizesMatch && c->grid.samples() == c->tessSamples;
    if (sizesMatch) evaluateUniformGrid(c->model->patches, c->grid, c->tessOut->data());
    planMs += std::chrono::duration<double, std::milli>(planned - start).count();
    evalMs += millisecondsSince(planned);
  });
  benchmark::DoNotOptimize(c->tessOut->data());
  if (!sizesMatch) {
    state.SkipWithError("the grid's sample count changed between setup and timing");
    return;
  }
  reportSampleCounters(state, c->tessSamples, seconds);
  const double iterations = double(state.iterations());
  state.counters["plan_ms"] = planMs / iterations;
  state.counters["eval_ms"] = evalMs / iterations;
  state.counters["pieces"] = double(c->pieces);
  state.counters["rings"] = double(c->model->patches.rings.size());
  state.counters["max_err_rel"] = c->tessError;
  state.counters["innermost_err_rel"] = c->tessInnermostError;
}

// The OSD methods share the sample set and the output buffer of their case.
UniformCase* osdCase(benchmark::State& state, const std::string& name, int p) {
  calibrateWriteFloor();
  try {
    UniformCase& c = uniformCase(name, p);
    if (!c.osd) {
      c.osd = std::make_unique<OsdUniformSamples>(c.model->mesh, p);
      c.osdOut = std::make_unique<TouchedBuffer<float>>(3 * c.osd->samples());
    }
    return &c;
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return nullptr;
  }
}

void reportOsd(benchmark::State& state, const UniformCase& c, double seconds) {
  reportSampleCounters(state, c.osd->samples(), seconds);
  state.counters["faces"] = c.osd->faces();
}

void BM_TessUniform_OsdBfr(benchmark::State& state, std::string name, int p) {
  UniformCase* c = osdCase(state, name, p);
  if (c == nullptr) return;
  if (!c->bfrPrepared) {
    c->osd->prepareBfr();
    c->bfrPrepared = true;
  }
  double seconds = timeWallIterations(state, [&] { c->osd->evaluateBfrPrepared(c->osdOut->data()); });
  benchmark::DoNotOptimize(c->osdOut->data());
  if (c->bfrError < 0) c->bfrError = osdLimitDeviation(*c->model, *c->osd, c->osdOut->data(), kBfrCheckFaceStride);
  reportOsd(state, *c, seconds);
  state.counters["max_err_rel"] = c->bfrError;  // Bfr's default approximation levels
}

void BM_TessUniform_OsdBfrPerFace(benchmark::State& state, std::string name, int p) {
  UniformCase* c = osdCase(state, name, p);
  if (c == nullptr) return;
  double seconds = timeWallIterations(state, [&] { c->osd->evaluateBfrPerFace(c->osdOut->data()); });
  benchmark::DoNotOptimize(c->osdOut->data());
  reportOsd(state, *c, seconds);
}

void BM_TessUniform_OsdEval(benchmark::State& state, std::string name, int p) {
  UniformCase* c = osdCase(state, name, p);
  if (c == nullptr) return;
  if (!c->evalPrepared) {
    try {
      c->osd->prepareOsdEval(c->stencilMs);
    } catch (const std::exception& e) {
      c->error = e.what();
    }
    c->evalPrepared = true;
  }
  if (!c->error.empty()) {
    state.SkipWithError(c->error.c_str());
    return;
  }
  double seconds = timeWallIterations(state, [&] { c->osd->evaluateOsdEval(c->osdOut->data()); });
  benchmark::DoNotOptimize(c->osdOut->data());
  if (c->evalVsBfr < 0) {
    if (!c->bfrPrepared) {
      c->osd->prepareBfr();
      c->bfrPrepared = true;
    }
    c->evalVsBfr = c->osd->maxDeviationFromBfr(c->osdOut->data(), kBfrCheckFaceStride) / c->model->diagonal;
  }
  reportOsd(state, *c, seconds);
  state.counters["patches"] = double(c->osd->patchCount());
  state.counters["stencil_ms_1thread"] = c->stencilMs;
  state.counters["vs_bfr_rel"] = c->evalVsBfr;
}

void registerUniform() {
  using Method = void (*)(benchmark::State&, std::string, int);
  const std::pair<const char*, Method> methods[] = {
      {"BM_TessUniform_Tessera", BM_TessUniform_Tessera},
      {"BM_TessUniform_OsdBfr", BM_TessUniform_OsdBfr},
      {"BM_TessUniform_OsdBfrPerFace", BM_TessUniform_OsdBfrPerFace},
      {"BM_TessUniform_OsdEval", BM_TessUniform_OsdEval},
  };
  // Case after case, so that the four methods of a case share its setup and buffers.
  for (const std::string& model : paperModels()) {
    for (int p : kUniformLevels) {
      for (const auto& [prefix, method] : methods) {
        std::string name = std::string(prefix) + "/" + model + "/" + std::to_string(p);
        benchmark::RegisterBenchmark(name.c_str(), method, model, p)
            ->UseManualTime()
            ->ComputeStatistics("min", fastestOf)
            ->Unit(benchmark::kMillisecond);
      }
    }
  }
}

const bool registered = [] {
  registerUniform();
  registerDepthEstimates();
  registerEtaSweep();
  registerTightness();
  benchmark::AddCustomContext("tess_threads", std::to_string(kTessThreads));
  benchmark::AddCustomContext("tess_models_dir", tessModelsDir());
  return true;
}();

}  // namespace
}  // namespace tessera::bench
