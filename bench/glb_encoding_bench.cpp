// GLB size and encoding time per encoding (docs/GLB.md, bench/GLB-RESULTS.md):
//
//   BM_GlbEncode/<model>/<eps>/<encoding>   writeGlb() of the mesh tessellate() made for that
//       encoding (its ε less the grid's error when positions are quantized), on both cores.
//       Counters: bytes, bytes per triangle, triangles, the size over the float file's, and the
//       grid's error over ε. The float case is the baseline, run beside the others in one process.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/glb_output.h"
#include "core/pipeline/preprocessing.h"
#include "reference/models.h"

namespace tessera::bench {
namespace {

constexpr const char* kPaperModels[] = {"bigguy", "monsterfrog", "armorguy", "t-rex", "car"};
constexpr double kTolerances[] = {1e-3, 1e-4};
constexpr GlbEncoding kEncodings[] = {GlbEncoding::kFloat, GlbEncoding::kQuantized,
                                      GlbEncoding::kMeshopt};

struct Case {
  TessellationResult result;
  TessellationOptions options;
  std::optional<PositionQuantization> positions;
};

struct Loaded {
  ControlMesh mesh;
  PatchSet patches;
};

const Loaded& loaded(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Loaded>> models;
  auto& entry = models[name];
  if (!entry) {
    entry = std::make_unique<Loaded>();
    entry->mesh = readObjFile(testing::modelsDir() + "/" + name + ".obj");
    entry->mesh.uvs.clear(), entry->mesh.uvIndices.clear();  // geometry only (bench/GLB-RESULTS.md's figures)
    entry->patches = buildPatchSet(entry->mesh);
  }
  return *entry;
}

Case prepare(const Loaded& m, double eps, GlbEncoding encoding) {
  Case c;
  c.options.accuracy = Accuracy::relative(eps);
  c.positions = reserveForEncoding(encoding, m.patches, c.options);
  c.result = tessellate(m.patches, m.mesh, c.options);
  return c;
}

void glbEncode(benchmark::State& state, const std::string& name, double eps, GlbEncoding encoding) {
  const Loaded& m = loaded(name);
  const Case c = prepare(m, eps, encoding);
  const GlbOptions options =
      glbOptionsFor({encoding, name, ""}, c.options, c.result.summary, c.positions);
  size_t bytes = 0;
  for (auto _ : state) {
    std::vector<uint8_t> glb = writeGlb(c.result.mesh, options);
    bytes = glb.size();
    benchmark::DoNotOptimize(glb.data());
  }
  static std::map<std::string, double> floatBytes;
  const std::string key = name + "/" + std::to_string(eps);
  if (encoding == GlbEncoding::kFloat) floatBytes[key] = double(bytes);
  const double triangles = double(c.result.summary.triangles);
  state.counters["bytes"] = double(bytes);
  state.counters["bytes_per_triangle"] = double(bytes) / triangles;
  state.counters["triangles"] = triangles;
  if (floatBytes.count(key)) state.counters["of_float"] = double(bytes) / floatBytes[key];
  state.counters["position_error_over_eps"] =
      c.positions ? c.positions->maxError / c.result.summary.tolerance : 0.0;
}

const bool registered = [] {
  for (const char* name : kPaperModels) {
    for (double eps : kTolerances) {
      for (GlbEncoding encoding : kEncodings) {
        char suffix[96];
        std::snprintf(suffix, sizeof suffix, "%s/%g/%s", name, eps, glbEncodingName(encoding));
        benchmark::RegisterBenchmark((std::string("BM_GlbEncode/") + suffix).c_str(), glbEncode,
                                     name, eps, encoding)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
  return true;
}();

}  // namespace
}  // namespace tessera::bench
