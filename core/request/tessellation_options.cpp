#include "core/request/tessellation_options.h"

#include <cmath>
#include <string>

#include "core/base/error.h"

namespace tessera {

void validateTessellationOptions(const TessellationOptions& o) {
  if (!std::isfinite(o.encodingReserve) || o.encodingReserve < 0) {
    throwInvalid("the encoding's reserve must be a finite number >= 0, got " + std::to_string(o.encodingReserve));
  }
  validateAccuracy(o.accuracy, o.accuracy.uniform() ? "uniform level" : o.accuracy.pixelAccurate() ? "pixel accuracy" : "tolerance");
  if (o.accuracy.uniform()) return;
  validateEta(o.eta, "eta");
  if (o.maxTriangles <= 0) throwInvalid("the triangle budget must be positive");
  if (o.accuracy.pixelAccurate() != o.camera.has_value()) {
    throwInvalid(o.camera ? "a camera was given without a pixel accuracy to set for it"
                          : "a pixel accuracy needs the camera it is for");
  }
  if (!o.camera) return;
  validateCamera(*o.camera, "camera");
  validatePixelsForViewport(o.accuracy.pixels, o.camera->width, o.camera->height, "pixel accuracy");
}

}  // namespace tessera
