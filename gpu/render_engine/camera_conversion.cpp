#include "gpu/render_engine/camera_conversion.h"

#include <climits>
#include <string>

#include "core/error.h"

namespace tessera::gpu {
namespace {

Vec3 toFloat(const Vec3d& v) {
  return Vec3(float(v.x), float(v.y), float(v.z));
}

uint32_t unsignedSide(const char* name, int pixels) {
  if (pixels < 0) {
    throwInvalid(std::string("camera ") + name + " is " + std::to_string(pixels) +
                 " pixels; it must be positive");
  }
  return static_cast<uint32_t>(pixels);
}

int signedSide(const char* name, uint32_t pixels) {
  if (pixels > uint32_t(INT_MAX)) {
    throwInvalid(std::string("camera ") + name + " of " + std::to_string(pixels) +
                 " pixels does not fit a planning camera");
  }
  return static_cast<int>(pixels);
}

}  // namespace

Camera toGpuCamera(const tessera::Camera& camera) {
  Camera out;
  out.eye = toFloat(camera.eye);
  out.target = toFloat(camera.target);
  out.up = toFloat(camera.up);
  out.fovYDegrees = static_cast<float>(camera.fovYDegrees);
  out.width = unsignedSide("width", camera.width);
  out.height = unsignedSide("height", camera.height);
  out.nearPlane = 0.0f;
  out.farPlane = 0.0f;
  return out;
}

tessera::Camera toCoreCamera(const Camera& camera) {
  tessera::Camera out;
  out.eye = Vec3d(camera.eye);
  out.target = Vec3d(camera.target);
  out.up = Vec3d(camera.up);
  out.fovYDegrees = camera.fovYDegrees;
  out.width = signedSide("width", camera.width);
  out.height = signedSide("height", camera.height);
  return out;
}

}  // namespace tessera::gpu
