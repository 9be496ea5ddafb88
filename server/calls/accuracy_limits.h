// The server's budgets on a request's accuracy, shared by Tessellate, Render and RenderSession:
// core checks that an accuracy makes sense (core/request/accuracy.h); these check what this server
// allows. `field` names the request's field in messages ("relative", "settings.pixel_accuracy").
#pragma once

#include <cstdint>
#include <string_view>

#include "core/mesh/control_mesh.h"
#include "core/request/accuracy.h"
#include "core/request/camera.h"
#include "server/meshes/mesh_metadata.h"

namespace tessera::server {

struct TessellationLimits {
  double minRelativeTolerance = 1e-6;
  double minPixelAccuracy = 0.05;
  int64_t maxTriangles = 50'000'000;
  int maxUniformLevel = 64;
  int64_t maxImagePixels = 16384LL * 16384LL;
};

// INVALID_ARGUMENT for a uniform level above max_uniform_level or pixels finer than
// min_pixel_accuracy: a request the server will never serve, which a retry cannot change.
// Tolerances wait for the mesh (toleranceOnMesh), pixels for its positions (checkPixelsOnMesh).
void checkAccuracyLimits(const Accuracy& accuracy, std::string_view field, const TessellationLimits& limits);

// ε in model units for an absolute or relative tolerance on the mesh `metadata` describes:
// FAILED_PRECONDITION when its bounding box is empty (a tolerance has no scale; only meshes stored
// before uploads refused them), INVALID_ARGUMENT for an absolute one larger than its diagonal or
// one finer than min_relative_tolerance of it.
double toleranceOnMesh(const Accuracy& accuracy, std::string_view field, const MeshMetadata& metadata,
                       const TessellationLimits& limits);

// The floor of every mode for a pixel accuracy: INVALID_ARGUMENT, naming the estimate and the
// limit, when the finest tolerance `accuracy` asks at `camera` anywhere on `mesh` (core's
// finestRelativeTolerance: at the nearest corner of its bounding box, which no piece's tolerance
// is below) is finer than min_relative_tolerance of the diagonal. Needs the mesh's positions;
// run before any preprocessing. Nothing for other accuracies.
void checkPixelsOnMesh(const Accuracy& accuracy, const Camera& camera, const ControlMesh& mesh,
                       std::string_view field, const TessellationLimits& limits);

}  // namespace tessera::server
