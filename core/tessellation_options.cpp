#include "core/tessellation_options.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/uniform_levels.h"

namespace tessera {

namespace {
bool finite(const Vec3d& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

void validateUniformLevel(int p) {
  if (p < 1 || p > kMaxUniformLevel) {
    throwInvalid("level must be between 1 and " + std::to_string(kMaxUniformLevel) + ", got " +
                 std::to_string(p));
  }
}

void validateTessellationOptions(const TessellationOptions& o) {
  if (!std::isfinite(o.encodingReserve) || o.encodingReserve < 0) {
    throwInvalid("the encoding's reserve must be a finite number >= 0, got " + std::to_string(o.encodingReserve));
  }
  if (o.uniformLevel != 0) {
    validateUniformLevel(o.uniformLevel);
    return;
  }
  if (!std::isfinite(o.tolerance) || o.tolerance <= 0) {
    throwInvalid("tolerance must be a positive finite number, got " + std::to_string(o.tolerance));
  }
  if (o.relativeTolerance && o.tolerance >= 1) {
    throwInvalid("a relative tolerance must be below 1 (a fraction of the bounding-box diagonal)");
  }
  if (!std::isfinite(o.eta) || o.eta < 0 || o.eta >= 1) {
    throwInvalid("eta must be in [0, 1) (0: single phase), got " + std::to_string(o.eta));
  }
  if (o.maxTriangles <= 0) throwInvalid("the triangle budget must be positive");
  if (!o.camera) return;
  const Camera& c = *o.camera;
  if (!finite(c.eye) || !finite(c.target) || !finite(c.up)) throwInvalid("camera vectors must be finite");
  if (length(c.target - c.eye) <= 0) throwInvalid("camera eye and target coincide");
  if (length(cross(c.target - c.eye, c.up)) <= 1e-12 * length(c.target - c.eye) * length(c.up)) {
    throwInvalid("camera up vector is zero or parallel to the view direction");
  }
  if (!(c.fovYDegrees > 0 && c.fovYDegrees < 180)) throwInvalid("field of view must be in (0, 180) degrees");
  if (c.width <= 0 || c.height <= 0 || c.width > 16384 || c.height > 16384) {
    throwInvalid("viewport size must be between 1x1 and 16384x16384");
  }
  if (!std::isfinite(o.pixelAccuracy) || o.pixelAccuracy <= 0) {
    throwInvalid("pixel accuracy must be a positive number of pixels");
  }
}

}  // namespace tessera
