#include "bench/tess_figures.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include "bench/tess_depth.h"
#include "bench/tess_osd.h"
#include "core/bounds/depth_tables.h"
#include "core/pipeline/tessellate.h"
#include "reference/bfr_reference.h"

namespace tessera::bench {
namespace {

constexpr double kFig6Tolerance = 0.005;   // × the smallest bounding-box side (paper, Fig. 6)
constexpr double kFig5Tolerance = 1e-3;    // × the bounding-box diagonal
constexpr int kBfrExactLevel = 10;         // Bfr is exact for pieces down to this Far level
constexpr size_t kTightnessTriangles = 20000;
constexpr int kCheckedPieces = 400;

// Bfr at approximation level 10 for one model at a time (its surfaces are built on demand).
testing::BfrReference& limitReference(const LoadedModel& model) {
  static std::string name;
  static std::unique_ptr<testing::BfrReference> reference;
  if (!reference || name != model.name) {
    reference.reset();
    reference = std::make_unique<testing::BfrReference>(model.mesh);
    name = model.name;
  }
  return *reference;
}

// ---- Fig. 6: depth estimation -----------------------------------------------------------------

void BM_DepthEstimate_Tessera(benchmark::State& state, std::string name, double eta) {
  const LoadedModel& model = loadedModel(name);
  const RingSet& rings = model.patches.rings;
  const double tolerance = eta * kFig6Tolerance * model.minBoxSide;
  for (size_t r = 0; r < rings.size(); ++r) estimateDepth(rings.rules(r), rings.ringPoints(r), tolerance);  // tables
  long depthSum = 0, levelSum = 0;
  int maxDepth = 0;
  for (auto _ : state) {
    depthSum = 0;
    maxDepth = 0;
    for (size_t r = 0; r < rings.size(); ++r) {
      int depth = estimateDepth(rings.rules(r), rings.ringPoints(r), tolerance).depth;
      depthSum += depth;
      maxDepth = std::max(maxDepth, depth);
    }
    benchmark::DoNotOptimize(depthSum);
  }
  for (size_t r = 0; r < rings.size(); ++r) levelSum += rings.levels[r];
  const double count = std::max<double>(1.0, double(rings.size()));
  state.counters["rings"] = double(rings.size());
  state.counters["avg_depth"] = double(depthSum) / count;
  state.counters["avg_total_depth"] = double(depthSum + levelSum) / count;  // + the ring's Far level
  state.counters["max_depth"] = maxDepth;
  state.counters["eta"] = eta;
  state.counters["s_per_ring"] = benchmark::Counter(
      double(rings.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_DepthEstimate_ControlMesh(benchmark::State& state, std::string name) {
  const LoadedModel& model = loadedModel(name);
  const RingSet& rings = model.patches.rings;
  const double tolerance = kFig6Tolerance * model.minBoxSide;
  auto start = std::chrono::steady_clock::now();
  for (size_t r = 0; r < rings.size(); ++r) controlMeshBounds(rings.rules(r));
  const double tablesMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  long depthSum = 0, hullSum = 0;  // hull: the plain convex-hull bound
  int maxDepth = 0;
  for (auto _ : state) {
    depthSum = 0;
    maxDepth = 0;
    for (size_t r = 0; r < rings.size(); ++r) {
      const RingRules rules = rings.rules(r);
      int depth = depthFromTable(controlMeshBounds(rules).polyhedron, ringRadius(rules, rings.ringPoints(r)), tolerance);
      depthSum += depth;
      maxDepth = std::max(maxDepth, depth);
    }
    benchmark::DoNotOptimize(depthSum);
  }
  long levelSum = 0;
  for (size_t r = 0; r < rings.size(); ++r) {
    const RingRules rules = rings.rules(r);
    hullSum += depthFromTable(controlMeshBounds(rules).hull, ringRadius(rules, rings.ringPoints(r)), tolerance);
    levelSum += rings.levels[r];
  }
  const double count = std::max<double>(1.0, double(rings.size()));
  state.counters["rings"] = double(rings.size());
  state.counters["avg_depth"] = double(depthSum) / count;
  state.counters["avg_total_depth"] = double(depthSum + levelSum) / count;
  state.counters["max_depth"] = maxDepth;
  state.counters["avg_depth_hull"] = double(hullSum) / count;
  state.counters["tables_ms_once"] = tablesMs;  // first model only: later ones reuse the kinds
  state.counters["s_per_ring"] = benchmark::Counter(
      double(rings.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// ---- Fig. 5: the η split ------------------------------------------------------------------------

void BM_TessEta(benchmark::State& state, std::string name, int eta10) {
  const LoadedModel& model = loadedModel(name);
  TessellationOptions options;
  options.accuracy = Accuracy::relative(kFig5Tolerance);
  options.eta = eta10 / 10.0;
  TessellationSummary summary;
  size_t ringTriangles = 0;
  double planMs = 0, meshMs = 0;
  double seconds = timeWallIterations(state, [&] {
    TessellationResult result = tessellate(model.patches, model.mesh, options);
    summary = result.summary;
    planMs += summary.planMs;
    meshMs += summary.tessellateMs;
    if (ringTriangles == 0) {
      for (uint32_t piece : result.mesh.trianglePiece) ringTriangles += result.plan.pieces[piece].kind != PieceKind::kRegular;
    }
  });
  (void)seconds;
  const double iterations = double(state.iterations());
  state.counters["triangles"] = double(summary.triangles);
  state.counters["ring_triangles"] = double(ringTriangles);
  state.counters["avg_depth"] = summary.averageDepth;
  state.counters["max_depth"] = summary.maxDepth;
  state.counters["pieces"] = double(summary.pieces);
  state.counters["plan_ms"] = planMs / iterations;
  state.counters["mesh_ms"] = meshMs / iterations;
  state.counters["bound_over_eps"] = summary.guaranteedBound / summary.tolerance;
}

// Fig. 5 proper: the singularities only. The same request on a copy of the patch set without its
// regular patches, so that plan and watertight triangulation cover only the ring pieces (FAS
// patches and innermost Béziers), the part η changes.
const PatchSet& ringsOnly(const LoadedModel& model) {
  static std::string name;
  static PatchSet rings;
  if (name != model.name) {
    rings = model.patches;
    rings.regular = RegularPatches{};
    name = model.name;
  }
  return rings;
}

void BM_TessEtaRings(benchmark::State& state, std::string name, int eta10) {
  const LoadedModel& model = loadedModel(name);
  const PatchSet& rings = ringsOnly(model);
  TessellationOptions options;
  options.accuracy = Accuracy::absolute(kFig5Tolerance * model.diagonal);  // the whole model's ε
  options.eta = eta10 / 10.0;
  TessellationSummary summary;
  double planMs = 0, meshMs = 0;
  timeWallIterations(state, [&] {
    summary = tessellate(rings, model.mesh, options).summary;
    planMs += summary.planMs;
    meshMs += summary.tessellateMs;
  });
  const double iterations = double(state.iterations());
  state.counters["triangles"] = double(summary.triangles);
  state.counters["avg_depth"] = summary.averageDepth;
  state.counters["max_depth"] = summary.maxDepth;
  state.counters["pieces"] = double(summary.pieces);
  state.counters["plan_ms"] = planMs / iterations;
  state.counters["mesh_ms"] = meshMs / iterations;
}

// ---- Tightness ---------------------------------------------------------------------------------

void BM_Tightness(benchmark::State& state, std::string name, double relative) {
  const LoadedModel& model = loadedModel(name);
  TessellationOptions options;
  options.accuracy = Accuracy::relative(relative);
  options.recordParameters = true;
  static const double kBarycentric[7][3] = {{1, 0, 0},     {0, 1, 0},   {0, 0, 1},          {0.5, 0.5, 0},
                                            {0, 0.5, 0.5}, {0.5, 0, 0.5}, {1 / 3.0, 1 / 3.0, 1 / 3.0}};
  double worst = 0, bound = 0, epsilon = 0;
  size_t sampled = 0, triangles = 0, deep = 0;
  for (auto _ : state) {
    TessellationResult result = tessellate(model.patches, model.mesh, options);
    testing::BfrReference& reference = limitReference(model);
    const TriangleMesh& mesh = result.mesh;
    triangles = mesh.triangleCount();
    epsilon = result.summary.tolerance;
    bound = result.summary.guaranteedBound;
    const size_t stride = std::max<size_t>(1, triangles / kTightnessTriangles);
    for (size_t tri = 0; tri < triangles; tri += stride) {
      const BezierPiece& piece = result.plan.pieces[mesh.trianglePiece[tri]];
      if (piece.depth > kBfrExactLevel) {
        ++deep;
        continue;
      }
      const double* st = &mesh.triangleST[6 * tri];
      for (const auto& b : kBarycentric) {
        double s = b[0] * st[0] + b[1] * st[2] + b[2] * st[4], t = b[0] * st[1] + b[1] * st[3] + b[2] * st[5];
        Vec3d onMesh, exact;
        for (int k = 0; k < 3; ++k) onMesh += Vec3d(mesh.positions[mesh.indices[3 * tri + k]]) * b[k];
        if (!reference.evaluate(piece.domain, s, t, exact)) continue;
        worst = std::max(worst, length(onMesh - exact));
      }
      ++sampled;
    }
  }
  state.counters["worst_over_eps"] = worst / epsilon;
  state.counters["bound_over_eps"] = bound / epsilon;
  state.counters["epsilon"] = epsilon;
  state.counters["triangles"] = double(triangles);
  state.counters["sampled_triangles"] = double(sampled);
  state.counters["skipped_deep"] = double(deep);
}

}  // namespace

double sampledLimitDeviation(const LoadedModel& model, const TessellationPlan& plan, const std::vector<size_t>& offsets,
                             const Vec3* samples, double& innermost) {
  testing::BfrReference& reference = limitReference(model);
  auto check = [&](size_t p) {
    const BezierPiece& piece = plan.pieces[p];
    double worst = 0;
    if (piece.depth > kBfrExactLevel) return worst;
    const int n = piece.level;
    for (int j : {0, n / 2, n}) {
      for (int i : {0, n / 2, n}) {
        Vec3d exact;
        if (!reference.evaluate(piece.domain, double(i) / n, double(j) / n, exact)) continue;
        Vec3d sample(samples[offsets[p] + size_t(j) * (n + 1) + i]);
        worst = std::max(worst, length(sample - exact));
      }
    }
    return worst;
  };
  double worst = 0;
  const size_t stride = std::max<size_t>(1, plan.pieces.size() / kCheckedPieces);
  for (size_t p = 0; p < plan.pieces.size(); p += stride) worst = std::max(worst, check(p));
  std::vector<size_t> approximated;
  for (size_t p = 0; p < plan.pieces.size(); ++p) {
    if (plan.pieces[p].kind == PieceKind::kInnermost) approximated.push_back(p);
  }
  innermost = 0;
  const size_t innerStride = std::max<size_t>(1, approximated.size() / kCheckedPieces);
  for (size_t k = 0; k < approximated.size(); k += innerStride) innermost = std::max(innermost, check(approximated[k]));
  innermost /= model.diagonal;
  return std::max(worst / model.diagonal, innermost);
}

double osdLimitDeviation(const LoadedModel& model, const OsdUniformSamples& osd, const float* samples,
                         int faceStride) {
  testing::BfrReference& reference = limitReference(model);
  double worst = 0;
  for (int f = 0; f < osd.faces(); f += faceStride) {
    for (size_t i = osd.faceBegin(f); i < osd.faceBegin(f + 1); ++i) {
      Vec3d exact;
      if (!reference.evaluateFace(f, -1, osd.uv(i)[0], osd.uv(i)[1], exact)) continue;
      worst = std::max(worst, length(Vec3d(samples[3 * i], samples[3 * i + 1], samples[3 * i + 2]) - exact));
    }
  }
  return worst / model.diagonal;
}

void registerDepthEstimates() {
  for (const std::string& model : paperModels()) {
    for (double eta : {0.5, 1.0}) {
      std::string name = "BM_DepthEstimate_Tessera/" + model + "/eta:" + (eta == 1.0 ? "1" : "0.5");
      benchmark::RegisterBenchmark(name.c_str(), BM_DepthEstimate_Tessera, model, eta)
          ->UseRealTime()
          ->ComputeStatistics("min", fastestOf)
          ->Unit(benchmark::kMicrosecond);
    }
    std::string name = "BM_DepthEstimate_ControlMesh/" + model;
    benchmark::RegisterBenchmark(name.c_str(), BM_DepthEstimate_ControlMesh, model)
        ->UseRealTime()
        ->ComputeStatistics("min", fastestOf)
        ->Unit(benchmark::kMicrosecond);
  }
}

void registerEtaSweep() {
  for (const std::string& model : paperModels()) {
    for (int eta10 = 0; eta10 <= 9; ++eta10) {
      std::string name = "BM_TessEtaRings/" + model + "/" + std::to_string(eta10);
      benchmark::RegisterBenchmark(name.c_str(), BM_TessEtaRings, model, eta10)
          ->UseManualTime()
          ->ComputeStatistics("min", fastestOf)
          ->Unit(benchmark::kMillisecond);
    }
    for (int eta10 = 0; eta10 <= 9; ++eta10) {
      std::string name = "BM_TessEta/" + model + "/" + std::to_string(eta10);
      benchmark::RegisterBenchmark(name.c_str(), BM_TessEta, model, eta10)
          ->UseManualTime()
          ->ComputeStatistics("min", fastestOf)
          ->Unit(benchmark::kMillisecond);
    }
  }
}

void registerTightness() {
  for (const std::string& model : paperModels()) {
    for (const char* eps : {"1e-2", "1e-3", "1e-4"}) {
      std::string name = std::string("BM_Tightness/") + model + "/" + eps;
      benchmark::RegisterBenchmark(name.c_str(), BM_Tightness, model, std::stod(eps))
          ->Iterations(1)
          ->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace tessera::bench
