// The in-process baseline for tools/load-test.sh's gRPC overhead measurement: the work a
// tessera-server does for a Tessellate call once the mesh's patch set is cached (core's
// tessellate() and writeGlb(), server/tessellation/cpu_engine.cpp), timed alone in this process.
//
//   tessera-inprocess-timing MODEL.obj --relative E --runs N [--warmup W] [--name NAME]
//
// Builds the patch set once (the server caches it per mesh), runs tessellate() + writeGlb() W
// times unmeasured (the first runs of a process pay for page faults and thread-pool start-up, as
// a server's first calls do), then N times measured, and prints JSON: the triangle count, the
// GLB size and every measured run's wall time in ms.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/mesh/obj_reader.h"
#include "core/output/glb_writer.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"

namespace {

struct Arguments {
  std::string model;
  std::string name;
  double relative = 0;
  int runs = 0;
  int warmup = 0;
};

bool parse(int argc, char** argv, Arguments& a) {
  for (int i = 1; i < argc; ++i) {
    std::string flag = argv[i];
    bool hasValue = i + 1 < argc;
    if (flag == "--relative" && hasValue) {
      a.relative = std::atof(argv[++i]);
    } else if (flag == "--runs" && hasValue) {
      a.runs = std::atoi(argv[++i]);
    } else if (flag == "--warmup" && hasValue) {
      a.warmup = std::atoi(argv[++i]);
    } else if (flag == "--name" && hasValue) {
      a.name = argv[++i];
    } else if (a.model.empty() && flag.rfind("--", 0) != 0) {
      a.model = flag;
    } else {
      return false;
    }
  }
  if (a.name.empty()) a.name = std::filesystem::path(a.model).stem().string();
  return !a.model.empty() && a.relative > 0 && a.relative < 1 && a.runs > 0 && a.runs <= 1000 &&
         a.warmup >= 0 && a.warmup <= 1000;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments arguments;
  if (!parse(argc, argv, arguments)) {
    std::fprintf(stderr,
                 "usage: tessera-inprocess-timing MODEL.obj --relative E --runs N (1..1000) "
                 "[--warmup W (0..1000)] [--name NAME]\n");
    return 2;
  }
  try {
    tessera::ControlMesh mesh = tessera::readObjFile(arguments.model);
    tessera::PatchSet patches = tessera::buildPatchSet(mesh);
    tessera::TessellationOptions options;
    options.accuracy = tessera::Accuracy::relative(arguments.relative);
    std::vector<double> milliseconds;
    int64_t triangles = 0;
    size_t glbBytes = 0;
    for (int run = 0; run < arguments.warmup + arguments.runs; ++run) {
      auto start = std::chrono::steady_clock::now();
      tessera::TessellationResult result = tessera::tessellate(patches, mesh, options);
      std::vector<uint8_t> glb = tessera::writeGlb(result.mesh, {.description = {.sourceName = arguments.name}});
      if (run >= arguments.warmup) {
        milliseconds.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count());
      }
      triangles = result.summary.triangles;
      glbBytes = glb.size();
    }
    std::printf(
        "{\"model\": \"%s\", \"relative\": %g, \"triangles\": %lld, \"glb_bytes\": %zu, "
        "\"runs_ms\": [",
        arguments.name.c_str(), arguments.relative, static_cast<long long>(triangles), glbBytes);
    for (size_t i = 0; i < milliseconds.size(); ++i) {
      std::printf("%s%.3f", i ? ", " : "", milliseconds[i]);
    }
    std::printf("]}\n");
    return 0;
  } catch (const tessera::TesseraError& e) {
    std::fprintf(stderr, "tessera-inprocess-timing: %s\n", e.what());
    return 3;
  }
}
