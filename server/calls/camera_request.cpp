#include "server/calls/camera_request.h"

#include <fmt/format.h>

#include <utility>

#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

// Presence is the proto's business; the values are core's.
Vec3d requireVec3(bool present, const v1::Vec3& v, std::string_view field, const char* part) {
  if (!present) throwInvalidArgument(fmt::format("{}.{}: is required", field, part));
  return Vec3d(v.x(), v.y(), v.z());
}

}  // namespace

Camera checkedCamera(const v1::Camera& c, std::string_view field, int maxSide, int64_t maxImagePixels) {
  const Camera camera{requireVec3(c.has_eye(), c.eye(), field, "eye"),
                      requireVec3(c.has_target(), c.target(), field, "target"),
                      requireVec3(c.has_up(), c.up(), field, "up"),
                      c.fov_y_deg(),
                      c.width(),
                      c.height()};
  for (auto [side, name] : {std::pair{c.width(), "width"}, std::pair{c.height(), "height"}}) {
    if (side < 1 || side > maxSide) {
      throwInvalidArgument(fmt::format("{}.{}: must be in [1, {}] pixels (got {})", field, name, maxSide, side));
    }
  }
  checkWithCore([&] { validateCamera(camera, field); });
  if (int64_t(c.width()) * c.height() > maxImagePixels) {
    throwResourceExhausted(fmt::format("{}: {}x{} pixels exceeds the server's max_image_pixels of {}", field,
                                       c.width(), c.height(), maxImagePixels));
  }
  return camera;
}

}  // namespace tessera::server
