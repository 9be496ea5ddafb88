#include "bench/tess_common.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <new>

#include "bench/write_floor.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "reference/models.h"

namespace tessera::bench {

std::string tessModelsDir() {
  if (const char* dir = std::getenv("TESSERA_MODELS_DIR")) return dir;
  // __FILE__ is <checkout>/bench/tess_common.cpp; the models sit in ../shared/models beside it.
  std::filesystem::path checkout = std::filesystem::path(__FILE__).parent_path().parent_path();
  return (checkout.parent_path() / "shared" / "models").string();
}

const std::vector<std::string>& adaptiveModels() {
  static const std::vector<std::string> names = {"bigguy",         "monsterfrog",  "armorguy",
                                                 "t-rex",          "car",          "catmark_bishop",
                                                 "catmark_rook",   "catmark_cubes_semisharp",
                                                 "catmark_torus_creases0"};
  return names;
}

TessellationOptions adaptiveOptions(double eps) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(eps);
  options.maxTriangles = 200'000'000;
  return options;
}

std::string modelObjPath(const std::string& name) {
  const std::string dir = testing::modelsDir();
  return name.rfind("catmark_", 0) == 0 ? dir + "/opensubdiv-shapes/" + name + ".obj" : dir + "/" + name + ".obj";
}

const ControlMesh& geometryMesh(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<ControlMesh>> meshes;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = meshes[name];
  if (!slot) {
    slot = std::make_unique<ControlMesh>(readObjFile(modelObjPath(name)));
    slot->uvs.clear(), slot->uvIndices.clear();
  }
  return *slot;
}

const LoadedModel& loadedModel(const std::string& name) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<LoadedModel>> models;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = models[name];
  if (!slot) {
    auto model = std::make_unique<LoadedModel>();
    model->name = name;
    model->mesh = readObjFile(tessModelsDir() + "/" + name + ".obj");
    model->mesh.uvs.clear(), model->mesh.uvIndices.clear();  // geometry only, as the baselines
    model->patches = buildPatchSet(model->mesh);
    Vec3d lo(model->patches.boundsMin), hi(model->patches.boundsMax);
    Vec3d side = hi - lo;
    model->diagonal = length(side);
    model->minBoxSide = std::min({side.x, side.y, side.z});
    slot = std::move(model);
  }
  return *slot;
}

void calibrateWriteFloor() {
  static std::once_flag once;
  std::call_once(once, [] {
    // write_floor.h's own fallback takes the best of 5 passes; the two-thread bandwidth on this
    // machine varies by up to 2× from pass to pass, so take the best of many passes and of every
    // store kind (as BM_WriteFloor does): the floor is then the strictest one seen.
    const size_t floats = kFloorBufferBytes / sizeof(float);
    float* buffer = static_cast<float*>(allocateTouched(kFloorBufferBytes));
    for (WriteMethod method : {WriteMethod::kStreamAvx2, WriteMethod::kStreamAvx512, WriteMethod::kMemset}) {
      if (!writeMethodAvailable(method)) continue;
      for (int pass = 0; pass < 20; ++pass) {
        double seconds = timedWrite(method, buffer, floats, kTessThreads, float(pass + 1));
        recordWriteBandwidth(double(kFloorBufferBytes) / seconds);
      }
    }
    freeTouched(buffer);
  });
}

void reportSampleCounters(benchmark::State& state, size_t samples, double seconds) {
  const double bytes = double(samples) * 3 * sizeof(float);
  const double perIteration = seconds / double(std::max<benchmark::IterationCount>(1, state.iterations()));
  const double floorSeconds = bytes / bestWriteBandwidth();
  state.counters["samples"] = double(samples);
  state.counters["bytes_written"] = bytes;
  state.counters["GB/s"] = bytes / perIteration / 1e9;
  state.counters["floor_ms"] = floorSeconds * 1e3;
  state.counters["x_floor"] = perIteration / floorSeconds;
  state.counters["floor_GB/s"] = bestWriteBandwidth() / 1e9;
}

TessCaseSlot& tessCaseSlot() {
  static TessCaseSlot slot;
  return slot;
}

double fastestOf(const std::vector<double>& values) {
  return *std::min_element(values.begin(), values.end());
}

}  // namespace tessera::bench
