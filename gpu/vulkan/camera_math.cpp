#include "gpu/vulkan/camera_math.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/request/camera.h"
#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace {

bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

Vec3d toDouble(const Vec3& v) {
  return Vec3d(v);
}

Vec3d normalized(const Vec3d& v) {
  return v * (1.0 / length(v));
}

void requireSide(const char* name, uint32_t pixels) {
  if (pixels == 0 || pixels > kMaxTargetSize) {
    throw RenderInputError("camera " + std::string(name) + " is " + std::to_string(pixels) +
                           " pixels; it must be between 1 and " + std::to_string(kMaxTargetSize));
  }
}

// Fits [near, far] to the bounds' sphere along the view direction. When the eye is inside
// the sphere, near becomes a small fraction of far: depth precision then falls off, but
// nothing in front of the eye is lost.
void fitPlanes(const Vec3d& eye, const Vec3d& forward, const SceneBounds& bounds, double& zNear,
               double& zFar) {
  if (bounds.empty) {
    zNear = 0.1;
    zFar = 100.0;
    return;
  }
  Vec3d lo = toDouble(bounds.min);
  Vec3d hi = toDouble(bounds.max);
  Vec3d centre = (lo + hi) * 0.5;
  double radius = 0.5 * length(hi - lo);
  double distance = dot(centre - eye, forward);
  double margin = std::max(radius, 1e-6 * std::max(1.0, length(centre))) * 0.01;
  zFar = distance + radius + margin;
  if (zFar <= 0.0) zFar = 1.0;  // everything is behind the eye: any planes give an empty frame
  zNear = std::max(distance - radius - margin, zFar * 1e-4);
}

}  // namespace

void validateCamera(const Camera& camera) {
  if (!finite(camera.eye) || !finite(camera.target) || !finite(camera.up)) {
    throw RenderInputError("camera eye, target and up must be finite (no NaN or infinity)");
  }
  Vec3d view = toDouble(camera.target) - toDouble(camera.eye);
  double viewLength = length(view);
  if (!(viewLength > 0.0)) throw RenderInputError("camera eye and target are the same point");
  double upLength = length(toDouble(camera.up));
  if (!(upLength > 0.0)) throw RenderInputError("camera up vector is zero");
  double sine = length(cross(view, toDouble(camera.up))) / (viewLength * upLength);
  if (!(sine > kMinUpSine)) throw RenderInputError("camera up vector is parallel to the view direction");
  if (!std::isfinite(camera.fovYDegrees) || camera.fovYDegrees <= 0.0f ||
      camera.fovYDegrees >= 180.0f) {
    throw RenderInputError("camera fovYDegrees must lie strictly between 0 and 180, got " +
                           std::to_string(camera.fovYDegrees));
  }
  requireSide("width", camera.width);
  requireSide("height", camera.height);
  bool explicitPlanes = camera.nearPlane != 0.0f || camera.farPlane != 0.0f;
  if (explicitPlanes && !(std::isfinite(camera.nearPlane) && std::isfinite(camera.farPlane) &&
                          camera.nearPlane > 0.0f && camera.farPlane > camera.nearPlane)) {
    throw RenderInputError(
        "camera near/far planes must satisfy 0 < near < far (or both be 0 "
        "to fit them to the scene)");
  }
}

SceneBounds boundsOf(std::span<const RenderPatch> patches) {
  SceneBounds b;
  for (const RenderPatch& p : patches) {
    for (const auto& c : p.controlPoints) {
      Vec3 v(c[0], c[1], c[2]);
      if (b.empty) {
        b.min = b.max = v;
        b.empty = false;
      }
      b.min = Vec3(std::min(b.min.x, v.x), std::min(b.min.y, v.y), std::min(b.min.z, v.z));
      b.max = Vec3(std::max(b.max.x, v.x), std::max(b.max.y, v.y), std::max(b.max.z, v.z));
    }
  }
  return b;
}

ViewProjection buildViewProjection(const Camera& camera, const SceneBounds& bounds) {
  Vec3d eye = toDouble(camera.eye);
  Vec3d f = normalized(toDouble(camera.target) - eye);
  Vec3d s = normalized(cross(f, toDouble(camera.up)));
  Vec3d u = cross(s, f);
  double zNear = camera.nearPlane;
  double zFar = camera.farPlane;
  if (zNear == 0.0 && zFar == 0.0) fitPlanes(eye, f, bounds, zNear, zFar);

  const double kPi = 3.14159265358979323846;
  double focal = 1.0 / std::tan(0.5 * camera.fovYDegrees * kPi / 180.0);
  double aspect = double(camera.width) / double(camera.height);
  // Rows of projection · view. Row 1 is negated: Vulkan's framebuffer y points down.
  double a = zFar / (zNear - zFar);
  double b = zNear * zFar / (zNear - zFar);
  double rows[4][4] = {
      {focal / aspect * s.x, focal / aspect * s.y, focal / aspect * s.z,
       -focal / aspect * dot(s, eye)},
      {-focal * u.x, -focal * u.y, -focal * u.z, focal * dot(u, eye)},
      {-a * f.x, -a * f.y, -a * f.z, a * dot(f, eye) + b},
      {f.x, f.y, f.z, -dot(f, eye)},
  };
  ViewProjection vp;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) vp.matrix[c * 4 + r] = static_cast<float>(rows[r][c]);
  }
  vp.nearPlane = static_cast<float>(zNear);
  vp.farPlane = static_cast<float>(zFar);
  return vp;
}

}  // namespace tessera::gpu
