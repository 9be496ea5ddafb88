#include "core/request/camera.h"

#include <cfloat>
#include <cmath>
#include <string>

#include "core/base/error.h"

namespace tessera {
namespace {

std::string at(std::string_view where, std::string_view part) {
  return std::string(where) + std::string(part) + ": ";
}

// Finite once rounded to float, as the renderer will hold it.
bool fitsFloat(const Vec3d& v) {
  for (double c : {v.x, v.y, v.z}) {
    if (!std::isfinite(c) || std::fabs(c) > FLT_MAX) return false;
  }
  return true;
}

std::string formatVec(const Vec3d& v) {
  return std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z);
}

}  // namespace

void validateCamera(const Camera& c, std::string_view where) {
  for (auto [v, part] : {std::pair{c.eye, ".eye"}, std::pair{c.target, ".target"}, std::pair{c.up, ".up"}}) {
    if (!fitsFloat(v)) {
      throwInvalid(at(where, part) + "coordinates must be finite single-precision numbers (got " + formatVec(v) + ")");
    }
  }
  // The view as the renderer sees it, rounded to float, and as the planner sees it.
  const Vec3d view = Vec3d(Vec3(c.target)) - Vec3d(Vec3(c.eye));
  const Vec3d up = Vec3d(Vec3(c.up));
  const double viewLength = length(view), upLength = length(up);
  if (!(viewLength > 0) || !(length(c.target - c.eye) > 0)) {
    throwInvalid(at(where, "") + "eye and target must be distinct points");
  }
  if (!(upLength > 0)) throwInvalid(at(where, ".up") + "must be non-zero");
  if (!(length(cross(view, up)) > kMinUpSine * viewLength * upLength)) {
    throwInvalid(at(where, ".up") + "must not be parallel to target - eye");
  }
  const float fov = float(c.fovYDegrees);
  if (!std::isfinite(c.fovYDegrees) || !(fov > 0.0f) || !(fov < 180.0f)) {
    throwInvalid(at(where, ".fov_y_deg") + "must be in (0, 180) degrees (got " + std::to_string(c.fovYDegrees) + ")");
  }
  for (auto [side, part] : {std::pair{c.width, ".width"}, std::pair{c.height, ".height"}}) {
    if (side < 1 || side > kMaxViewportSide) {
      throwInvalid(at(where, part) + "must be in [1, " + std::to_string(kMaxViewportSide) + "] pixels (got " +
                   std::to_string(side) + ")");
    }
  }
}

}  // namespace tessera
