// Measures the peak resident memory of preprocessing and of tessellation (with the GLB) on real
// meshes beside core's estimates of them (core/pipeline/memory_estimates.h), which a server admits jobs
// by: every estimate must sit above what was measured. Writes bench/MEMORY-RESULTS.md's table.
//
//   tessera-memory-fit MODEL.obj... [--tolerances 1e-2,1e-3,1e-4] [--levels 3,5]
#include <malloc.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/output/glb_writer.h"
#include "core/pipeline/memory_estimates.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"

namespace {

using namespace tessera;

int64_t statusBytes(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(field, 0) == 0) return std::stoll(line.substr(std::strlen(field))) * 1024;
  }
  return -1;
}

// Gives freed memory back and restarts the kernel's peak (VmHWM) at the resident size now.
int64_t restartPeak() {
  malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
  return statusBytes("VmRSS:");
}

double mib(int64_t bytes) { return double(bytes) / double(1 << 20); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Peak memory of preprocessing and tessellation beside core's estimates");
  std::vector<std::string> models;
  std::vector<double> tolerances{1e-2, 1e-3, 1e-4};
  app.add_option("models", models, "OBJ files")->required();
  std::vector<int> levels;
  app.add_option("--tolerances", tolerances, "Relative tolerances to tessellate at")->delimiter(',');
  app.add_option("--levels", levels, "Uniform levels to tessellate at")->delimiter(',');
  CLI11_PARSE(app, argc, argv);

  std::printf("| model | stage | size | measured peak MiB | estimate MiB | estimate / measured |\n");
  std::printf("|---|---|---:|---:|---:|---:|\n");
  for (const std::string& path : models) {
    const ControlMesh mesh = readObjFile(path);
    const std::string name = path.substr(path.find_last_of('/') + 1);
    int64_t estimated = 0, refined = 0;
    PreprocessingOptions options;
    options.beforeRefining = [&](int64_t vertices) { estimated = vertices; };
    options.afterRefining = [&](int64_t vertices) { refined = vertices; };
    int64_t rest = restartPeak();
    const PatchSet patches = buildPatchSet(mesh, options);
    int64_t peak = statusBytes("VmHWM:") - rest;
    const int64_t preprocessing = preprocessingBytes(mesh, refined);
    std::printf("| %s | preprocessing | %lld refined vertices (estimated %lld) | %.0f | %.0f | %.2f |\n", name.c_str(),
                (long long)refined, (long long)estimated, mib(peak), mib(preprocessing), double(preprocessing) / peak);
    std::vector<TessellationOptions> requests;
    for (double tolerance : tolerances) {
      requests.emplace_back().accuracy = Accuracy::relative(tolerance);
    }
    for (int level : levels) requests.emplace_back().accuracy = Accuracy::uniformLevel(level);
    for (TessellationOptions tessellation : requests) {
      tessellation.maxTriangles = int64_t(1) << 40;
      rest = restartPeak();
      int64_t triangles = 0;
      {
        const TessellationResult result = tessellate(patches, mesh, tessellation);
        const std::vector<uint8_t> glb = writeGlb(result.mesh, {.description = {.sourceName = name}});
        triangles = result.summary.triangles;
      }
      peak = statusBytes("VmHWM:") - rest;
      const int64_t estimate = tessellationBytes(triangles);
      const std::string at = tessellation.accuracy.uniform() ? "uniform level " + std::to_string(tessellation.accuracy.level)
                                                           : std::to_string(tessellation.accuracy.tolerance);
      std::printf("| %s | tessellation + GLB at %s | %lld triangles | %.0f | %.0f | %.2f |\n", name.c_str(), at.c_str(),
                  (long long)triangles, mib(peak), mib(estimate), double(estimate) / double(peak));
    }
  }
  return 0;
}
