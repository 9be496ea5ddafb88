#include "server/calls/accuracy_limits.h"

#include <fmt/format.h>

#include "core/pipeline/preprocessing.h"
#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

// `mesh`: "mesh ID", or "the mesh".
[[noreturn]] void throwEmptyBox(std::string_view mesh) {
  throwStatus(grpc::StatusCode::FAILED_PRECONDITION,
              fmt::format("{} has an empty bounding box, so a tolerance has no scale", mesh));
}

}  // namespace

void checkAccuracyLimits(const Accuracy& accuracy, std::string_view field, const TessellationLimits& limits) {
  if (accuracy.uniform() && accuracy.level > limits.maxUniformLevel) {
    throwInvalidArgument(fmt::format("{}: {} is above the server's max_uniform_level of {}", field, accuracy.level,
                                     limits.maxUniformLevel));
  }
  if (accuracy.pixelAccurate() && accuracy.pixels < limits.minPixelAccuracy) {
    throwInvalidArgument(fmt::format("{}: {} is finer than the server's min_pixel_accuracy of {}", field,
                                     accuracy.pixels, limits.minPixelAccuracy));
  }
}

double toleranceOnMesh(const Accuracy& accuracy, std::string_view field, const MeshMetadata& metadata,
                       const TessellationLimits& limits) {
  const double diagonal = metadata.boundsDiagonal();
  if (!(diagonal > 0)) throwEmptyBox("mesh " + metadata.id);
  const double epsilon = accuracy.epsilonFor(diagonal);
  if (accuracy.mode == Accuracy::Mode::kAbsolute && epsilon > diagonal) {
    throwInvalidArgument(
        fmt::format("{}: {} is larger than the mesh's bounding-box diagonal ({})", field, epsilon, diagonal));
  }
  if (epsilon < limits.minRelativeTolerance * diagonal) {
    throwInvalidArgument(fmt::format("{}: a tolerance of {} ({} of the bounding-box diagonal) is finer than the "
                                     "server's min_relative_tolerance of {}",
                                     field, epsilon, epsilon / diagonal, limits.minRelativeTolerance));
  }
  return epsilon;
}

void checkPixelsOnMesh(const Accuracy& accuracy, const Camera& camera, const ControlMesh& mesh,
                       std::string_view field, const TessellationLimits& limits) {
  if (!accuracy.pixelAccurate()) return;
  TessellationOptions options;
  options.accuracy = accuracy;
  options.camera = camera;
  const double finest = finestRelativeTolerance(mesh, options);
  if (!(finest > 0)) throwEmptyBox("the mesh");
  if (finest >= limits.minRelativeTolerance) return;
  throwInvalidArgument(fmt::format(
      "{}: pixel accuracy {} px at this camera asks {:.2g} of the bounding-box diagonal at the mesh's nearest "
      "point, finer than the server's minimum {} (min_relative_tolerance); move the camera back, widen "
      "fov_y_deg or raise the pixel accuracy",
      field, accuracy.pixels, finest, limits.minRelativeTolerance));
}

}  // namespace tessera::server
