// The one pinhole camera of a request, from the RPC to the planner and the renderer: it looks
// from `eye` towards `target` with `up` roughly up and a full vertical field of view; the
// horizontal one follows from width / height. Pixel-accurate tolerances are set for it
// (core/surface/tolerance_model.h) and frames are drawn through it (gpu/render_engine converts it once
// to the renderer's single-precision form).
#pragma once

#include <string_view>

#include "core/base/vec3.h"

namespace tessera {

struct Camera {
  Vec3d eye, target, up{0, 1, 0};
  double fovYDegrees = 45;
  int width = 1920, height = 1080;
};

// The smallest sine of the angle between up and the view direction: below it the camera's roll
// is undefined. The renderer works in single precision, where an angle of ~1e-7 radians is lost
// to rounding, so every caller (planning and drawing) uses this one bound.
inline constexpr double kMinUpSine = 1e-6;
inline constexpr int kMaxViewportSide = 16384;

// Throws TesseraError (kInvalidInput) naming `where` and the part at fault ("pixel.camera.up:
// ...") unless: eye, target and up are finite in single precision (the renderer's), eye and
// target are distinct, up is non-zero and not within kMinUpSine of the view direction, the field
// of view is in (0, 180) degrees, and each side is in [1, kMaxViewportSide] pixels.
void validateCamera(const Camera& camera, std::string_view where);

}  // namespace tessera
