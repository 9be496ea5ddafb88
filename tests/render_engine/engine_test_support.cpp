#include "tests/render_engine/engine_test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "reference/models.h"

namespace tessera::testing {

const LoadedModel& loadModel(const std::string& name) {
  static std::map<std::string, std::unique_ptr<LoadedModel>> models;
  auto found = models.find(name);
  if (found != models.end()) return *found->second;
  std::string path = name.rfind("catmark_", 0) == 0
                         ? modelsDir() + "/opensubdiv-shapes/" + name + ".obj"
                         : modelsDir() + "/" + name + ".obj";
  auto model = std::make_unique<LoadedModel>();
  model->name = name;
  model->mesh = readObjFile(path);
  model->patches = buildPatchSet(model->mesh);
  Vec3d lo(model->patches.boundsMin), hi(model->patches.boundsMax);
  model->centre = (lo + hi) * 0.5;
  model->radius = 0.5 * length(hi - lo);
  return *(models[name] = std::move(model));
}

gpu::FrameEngine& testEngine() {
  static gpu::FrameEngine engine = [] {
    gpu::DeviceSelection selection = gpu::DeviceSelection::fromEnvironment();
    selection.validation = true;
    return gpu::FrameEngine::create(selection);
  }();
  return engine;
}

void expectNoValidationMessages() {
  for (const std::string& m : testEngine().renderer().takeValidationMessages()) {
    ADD_FAILURE() << "validation: " << m;
  }
}

tessera::Camera framedCamera(const LoadedModel& model, Vec3d direction, double fovYDegrees,
                             int width, int height, Vec3d targetOffset, double zoom) {
  tessera::Camera camera;
  double halfY = fovYDegrees * M_PI / 360.0;
  double halfX = std::atan(std::tan(halfY) * width / height);
  double distance = 1.05 * model.radius / std::sin(std::min(halfX, halfY)) / zoom;
  Vec3d d = direction * (1.0 / length(direction));
  camera.target = model.centre + targetOffset * model.radius;
  camera.eye = camera.target + d * distance;
  camera.up = std::abs(d.y) > 0.9 ? Vec3d(0, 0, -1) : Vec3d(0, 1, 0);
  camera.fovYDegrees = fovYDegrees;
  camera.width = width;
  camera.height = height;
  return camera;
}

void dumpFrame(const gpu::Frame& frame, const std::string& name) {
  const char* dir = std::getenv("TESSERA_TEST_DUMP_DIR");
  if (dir == nullptr) return;
  std::ofstream out(std::string(dir) + "/" + name + ".ppm", std::ios::binary);
  out << "P6\n" << frame.width << " " << frame.height << "\n255\n";
  for (size_t i = 0; i < size_t(frame.width) * frame.height; ++i) {
    out.write(reinterpret_cast<const char*>(&frame.rgba[4 * i]), 3);
  }
}

}  // namespace tessera::testing
