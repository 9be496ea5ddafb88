#include "gpu/render_engine/camera_conversion.h"

namespace tessera::gpu {

Camera toGpuCamera(const tessera::Camera& camera) {
  Camera out;
  out.eye = Vec3(camera.eye);
  out.target = Vec3(camera.target);
  out.up = Vec3(camera.up);
  out.fovYDegrees = static_cast<float>(camera.fovYDegrees);
  out.width = static_cast<uint32_t>(camera.width);
  out.height = static_cast<uint32_t>(camera.height);
  out.nearPlane = 0.0f;
  out.farPlane = 0.0f;
  return out;
}

}  // namespace tessera::gpu
