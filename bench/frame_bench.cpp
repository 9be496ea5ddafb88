// tessera-frame-bench: whole frames of Catmull-Clark models through the frame engine at
// 1920×1080, in the spirit of the paper's Fig. 7/8 (stage breakdown of pixel-accurate and
// uniform p = 64 rendering) and Table 3 (triangles per base face, ring depths over 100 views).
//
//   tessera-frame-bench                                    # everything
//   tessera-frame-bench --benchmark_filter=Frame/bigguy    # frame breakdown only
//   TESSERA_MODELS_DIR=... TESSERA_VK_DEVICE=llvmpipe tessera-frame-bench
//
// Frame counters (mean per frame, ms): plan_ms (CPU planning: ring depths, pieces, levels),
// patches_ms (CPU: frustum test, splitting, packing), tess_ms (GPU tessellation), raster_ms
// (raster + Blinn-Phong), crack_ms (crack filling), gpu_ms (the frame's GPU work), frame_ms
// (the whole engine call, uploads and readback included), Mtris, pieces. Each iteration draws
// the next of kFrameViews views taken from the Table 3 sweep.
// Table 3 counters: tri_per_face, avg_depth / max_depth (FAS steps per ring, Eq. (4)),
// avg_level / max_level (Far isolation level + FAS steps), over 10 × 10 views, planning only.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "gpu/render_engine/frame_engine.h"
#include "gpu/render_engine/view_sweep.h"

namespace tessera::gpu {
namespace {

constexpr int kWidth = 1920, kHeight = 1080;
constexpr int kFrameViews = 4;  // of the 100 sweep views: 0, 25, 50, 75

struct Model {
  ControlMesh mesh;
  PatchSet patches;
};

const Model& model(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Model>> models;
  auto& m = models[name];
  if (!m) {
    const char* dir = std::getenv("TESSERA_MODELS_DIR");
    m = std::make_unique<Model>();
    m->mesh = readObjFile(std::string(dir ? dir : TESSERA_MODELS_DIR) + "/" + name + ".obj");
    m->patches = buildPatchSet(m->mesh);
  }
  return *m;
}

FrameEngine& engine() {
  static FrameEngine e = FrameEngine::create(DeviceSelection::fromEnvironment());
  return e;
}

ViewSweep paperSweep() {
  ViewSweep sweep;
  sweep.width = kWidth;
  sweep.height = kHeight;
  return sweep;
}

void frames(benchmark::State& state, const std::string& name, int uniformLevel) {
  const Model& m = model(name);
  std::vector<tessera::Camera> sweep = sweepCameras(m.patches, paperSweep());
  std::vector<FrameRequest> requests;
  for (int v = 0; v < kFrameViews; ++v) {
    FrameRequest r;
    r.camera = sweep[size_t(v) * sweep.size() / kFrameViews];
    r.maxTriangles = 100'000'000;
    if (uniformLevel > 0) {
      r.accuracy = Accuracy::uniformLevel(uniformLevel);
    }
    requests.push_back(r);
  }
  engine().render(m.patches, requests[0]);  // warm-up: allocations, first pipeline use
  double plan = 0, patches = 0, tess = 0, raster = 0, crack = 0, gpu = 0, total = 0, tris = 0,
         pieces = 0;
  size_t next = 0;
  for (auto _ : state) {
    EngineFrame f = engine().render(m.patches, requests[next++ % requests.size()]);
    plan += f.timings.planMs;
    patches += f.timings.patchesMs;
    tess += f.timings.tessellationMs;
    raster += f.timings.rasterShadingMs;
    crack += f.timings.crackFillingMs;
    gpu += f.timings.gpuTotalMs;
    total += f.timings.totalMs;
    tris += double(f.statistics.triangles);
    pieces += double(f.statistics.pieces);
    benchmark::DoNotOptimize(f.frame.rgba.data());
  }
  double n = double(state.iterations());
  state.counters["plan_ms"] = plan / n;
  state.counters["patches_ms"] = patches / n;
  state.counters["tess_ms"] = tess / n;
  state.counters["raster_ms"] = raster / n;
  state.counters["crack_ms"] = crack / n;
  state.counters["gpu_ms"] = gpu / n;
  state.counters["frame_ms"] = total / n;
  state.counters["Mtris"] = tris / n / 1e6;
  state.counters["pieces"] = pieces / n;
}

void table3(benchmark::State& state, const std::string& name) {
  const Model& m = model(name);
  int baseFaces = m.mesh.faceCount() - int(m.mesh.holes.size());
  SweepStatistics s;
  for (auto _ : state) s = sweepStatistics(m.patches, baseFaces, paperSweep());
  state.counters["views"] = s.views;
  state.counters["tri_per_face"] = s.averageTrianglesPerBaseFace;
  state.counters["avg_depth"] = s.averageRingDepth;
  state.counters["max_depth"] = s.maxRingDepth;
  state.counters["avg_level"] = s.averageRingLevel;
  state.counters["max_level"] = s.maxRingLevel;
  state.counters["plan_ms"] = s.averagePlanMs;
}

void registerAll() {
  for (const char* name : {"bigguy", "monsterfrog"}) {
    std::string n = name;
    benchmark::RegisterBenchmark(("Frame/" + n + "/pixel_accurate").c_str(),
                                 [n](benchmark::State& s) { frames(s, n, 0); })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(2 * kFrameViews)
        ->UseRealTime();
    benchmark::RegisterBenchmark(("Frame/" + n + "/uniform64").c_str(),
                                 [n](benchmark::State& s) { frames(s, n, 64); })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(kFrameViews)
        ->UseRealTime();
    benchmark::RegisterBenchmark(("Table3/" + n).c_str(),
                                 [n](benchmark::State& s) { table3(s, n); })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1)
        ->UseRealTime();
  }
}

}  // namespace
}  // namespace tessera::gpu

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  tessera::gpu::registerAll();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
