#include "server/calls/accuracy_limits.h"

#include <fmt/format.h>

#include "server/calls/status_error.h"

namespace tessera::server {

void checkAccuracyLimits(const Accuracy& accuracy, std::string_view field, const TessellationLimits& limits) {
  if (accuracy.uniform() && accuracy.level > limits.maxUniformLevel) {
    throwInvalidArgument(fmt::format("{}: {} is above the server's max_uniform_level of {}", field, accuracy.level,
                                     limits.maxUniformLevel));
  }
  if (accuracy.pixelAccurate() && accuracy.pixels < limits.minPixelAccuracy) {
    throwResourceExhausted(fmt::format("{}: {} is finer than the server's min_pixel_accuracy of {}", field,
                                       accuracy.pixels, limits.minPixelAccuracy));
  }
}

double toleranceOnMesh(const Accuracy& accuracy, std::string_view field, const MeshMetadata& metadata,
                       const TessellationLimits& limits) {
  const double diagonal = metadata.boundsDiagonal();
  if (!(diagonal > 0)) {
    throwStatus(grpc::StatusCode::FAILED_PRECONDITION,
                fmt::format("mesh {} has an empty bounding box, so a tolerance has no scale", metadata.id));
  }
  const double epsilon = accuracy.epsilonFor(diagonal);
  if (accuracy.mode == Accuracy::Mode::kAbsolute && epsilon > diagonal) {
    throwInvalidArgument(
        fmt::format("{}: {} is larger than the mesh's bounding-box diagonal ({})", field, epsilon, diagonal));
  }
  if (epsilon < limits.minRelativeTolerance * diagonal) {
    throwResourceExhausted(fmt::format("{}: a tolerance of {} ({} of the bounding-box diagonal) is finer than the "
                                       "server's min_relative_tolerance of {}",
                                       field, epsilon, epsilon / diagonal, limits.minRelativeTolerance));
  }
  return epsilon;
}

}  // namespace tessera::server
