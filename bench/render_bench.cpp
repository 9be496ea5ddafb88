// tessera-render-bench: frame timings of the Vulkan renderer at 1920×1080, in the spirit of the
// paper's Fig. 7/8 (uniform levels and mixed per-edge levels; stage breakdown from GPU
// timestamps). The scene is a sphere of 6·k² bicubic patches filling most of the frame.
//
//   tessera-render-bench --benchmark_filter=Uniform/16
//   TESSERA_VK_DEVICE=llvmpipe tessera-render-bench
//
// Counters: tess_ms, raster_ms, crack_ms (GPU timestamps), gpu_ms (submission to fence),
// host_ms (whole render() call with upload and readback), Mtris (triangles per frame / 1e6).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "gpu/vulkan/renderer.h"

namespace tessera::gpu {
namespace {

// Interpolating (not exact) bicubic patches on the unit sphere: control points are the sphere
// points of a cube-face lattice. Enough for timing; tests use exact shared edges.
std::vector<RenderPatch> spherePatches(int k, uint32_t level, bool mixedLevels) {
  const double faces[6][3][3] = {
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}}};
  std::vector<RenderPatch> patches;
  uint32_t id = 0;
  for (const auto& f : faces) {
    for (int b = 0; b < k; ++b) {
      for (int a = 0; a < k; ++a) {
        RenderPatch p{};
        for (int j = 0; j < 4; ++j) {
          for (int i = 0; i < 4; ++i) {
            double s = -1.0 + 2.0 * (3 * a + i) / (3.0 * k);
            double t = -1.0 + 2.0 * (3 * b + j) / (3.0 * k);
            double c[3];
            for (int d = 0; d < 3; ++d) c[d] = f[0][d] + s * f[1][d] + t * f[2][d];
            double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
            for (int d = 0; d < 3; ++d) p.controlPoints[4 * j + i][d] = float(c[d] / len);
          }
        }
        for (int e = 0; e < 4; ++e) {
          // Mixed: levels level/2 .. level, varying by patch and edge (not crack-free).
          uint32_t vary = mixedLevels ? (id * 7 + e * 3) % (level / 2 + 1) : 0;
          p.edgeLevels[e] = level - vary;
        }
        p.patchId = id++;
        patches.push_back(p);
      }
    }
  }
  return patches;
}

Renderer& sharedRenderer() {
  static Renderer renderer = Renderer::create(DeviceSelection::fromEnvironment());
  return renderer;
}

void runFrames(benchmark::State& state, bool mixed, GeometryPath path) {
  int k = static_cast<int>(state.range(0));
  uint32_t level = static_cast<uint32_t>(state.range(1));
  std::vector<RenderPatch> patches = spherePatches(k, level, mixed);
  Camera camera;
  camera.eye = Vec3(0.0f, 0.4f, 2.6f);
  camera.width = 1920;
  camera.height = 1080;
  RenderOptions options;
  options.crackFilling = state.range(2) != 0;
  options.path = path;
  Renderer& renderer = sharedRenderer();
  const Frame first = renderer.render(patches, camera, options);  // warm-up: allocations, pipelines
  double tess = 0, raster = 0, crack = 0, gpu = 0, host = 0, tris = 0;
  for (auto _ : state) {
    Frame frame = renderer.render(patches, camera, options);
    tess += frame.timings.tessellationMs;
    raster += frame.timings.rasterShadingMs;
    crack += frame.timings.crackFillingMs;
    gpu += frame.timings.gpuTotalMs;
    host += frame.timings.hostTotalMs;
    tris += double(frame.trianglesGenerated);
  }
  double n = double(state.iterations());
  state.counters["patches"] = double(patches.size());
  state.counters["tess_ms"] = tess / n;
  state.counters["raster_ms"] = raster / n;
  state.counters["crack_ms"] = crack / n;
  state.counters["gpu_ms"] = gpu / n;
  state.counters["host_ms"] = host / n;
  state.counters["Mtris"] = tris / n / 1e6;
  state.SetLabel(renderer.info().name + (first.pathUsed == GeometryPath::kMeshShader
                                              ? ", mesh shaders"
                                              : ", compute"));
}

// The device's own choice (mesh shaders where it has them), and the compute path forced, so that
// a GPU with mesh shaders times both paths in one process.
void Uniform(benchmark::State& state) {
  runFrames(state, false, GeometryPath::kAuto);
}
void UniformCompute(benchmark::State& state) {
  runFrames(state, false, GeometryPath::kCompute);
}
void MixedLevels(benchmark::State& state) {
  runFrames(state, true, GeometryPath::kAuto);
}

// Args: {k (6·k² patches), level, crack filling}. k = 24 gives 3456 patches.
BENCHMARK(Uniform)
    ->Args({24, 4, 1})
    ->Args({24, 8, 1})
    ->Args({24, 16, 1})
    ->Args({24, 16, 0})
    ->Args({24, 32, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK(UniformCompute)
    ->Args({24, 16, 1})
    ->Args({24, 32, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK(MixedLevels)->Args({24, 16, 1})->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace tessera::gpu

BENCHMARK_MAIN();
