// Shared pieces of the frame-engine tests: models loaded once per process, the engine on the
// test device (validation requested, used where the layer is installed), cameras framed on a
// model, pixel counts, and a PPM dump for debugging.
#pragma once

#include <string>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"
#include "gpu/render_engine/frame_engine.h"

namespace tessera::testing {

struct LoadedModel {
  std::string name;
  ControlMesh mesh;
  PatchSet patches;
  Vec3d centre;
  double radius = 0;  // of the bounding box's sphere
};

// "bigguy", "monsterfrog" (models/) or an OpenSubdiv shape name ("catmark_edgecorner"); loaded
// and reduced to patches on first use.
const LoadedModel& loadModel(const std::string& name);

// The engine for tests: device from TESSERA_VK_DEVICE, validation requested.
gpu::FrameEngine& testEngine();
void expectNoValidationMessages();

// A camera looking at the model's centre (moved by `targetOffset` radii) from `direction`, at
// the distance where the bounding sphere fits the view, divided by `zoom`.
tessera::Camera framedCamera(const LoadedModel& model, Vec3d direction, double fovYDegrees,
                             int width, int height, Vec3d targetOffset = {}, double zoom = 1);

// Writes the frame as PPM into $TESSERA_TEST_DUMP_DIR when that is set (debugging only).
void dumpFrame(const gpu::Frame& frame, const std::string& name);

}  // namespace tessera::testing
