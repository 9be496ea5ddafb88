#include "server/tessellation/tessellate_request.h"

#include <fmt/format.h>

#include <cmath>

#include "server/calls/camera_request.h"
#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

constexpr double kDefaultEta = 0.5;
constexpr double kDefaultPixelAccuracy = 0.5;

Camera checkCamera(const v1::PixelTolerance& pixel, const TessellationLimits& limits) {
  if (!pixel.has_camera()) throwInvalidArgument("pixel.camera: is required");
  return checkedCamera(pixel.camera(), "pixel.camera", kMaxViewportSide, limits.maxImagePixels);
}

double checkPixelAccuracy(const v1::PixelTolerance& pixel, const Camera& camera,
                          const TessellationLimits& limits) {
  double accuracy = pixel.has_pixel_accuracy() ? pixel.pixel_accuracy() : kDefaultPixelAccuracy;
  checkWithCore([&] {
    validatePositiveFinite(accuracy, "pixel.pixel_accuracy");
    validatePixelsForViewport(accuracy, camera.width, camera.height, "pixel.pixel_accuracy");
  });
  checkAccuracyLimits(Accuracy::pixel(accuracy), "pixel.pixel_accuracy", limits);
  return accuracy;
}

void checkTolerance(const v1::TessellateRequest& request, const TessellationLimits& limits) {
  switch (request.tolerance_case()) {
    case v1::TessellateRequest::kAbsolute:
      return checkWithCore([&] { validateTolerance(request.absolute(), false, "absolute"); });
    case v1::TessellateRequest::kRelative:
      return checkWithCore([&] { validateTolerance(request.relative(), true, "relative"); });
    case v1::TessellateRequest::kPixel: {
      Camera camera = checkCamera(request.pixel(), limits);
      checkPixelAccuracy(request.pixel(), camera, limits);
      return;
    }
    case v1::TessellateRequest::TOLERANCE_NOT_SET:
      if (!request.has_uniform_level()) {
        throwInvalidArgument(
            "tolerance: one of absolute, relative or pixel is required (or a uniform_level)");
      }
      return;
  }
}

}  // namespace

void checkTessellateRequest(const v1::TessellateRequest& request, const TessellationLimits& limits) {
  checkTolerance(request, limits);
  if (request.has_eta()) {
    double eta = request.eta();
    if (!std::isfinite(eta) || eta < 0 || eta >= 1) {
      throwInvalidArgument(fmt::format("eta: must be in [0, 1) (got {})", eta));
    }
  }
  if (request.has_uniform_level()) {
    checkWithCore([&] { validateUniformLevel(request.uniform_level(), "uniform_level"); });
    checkAccuracyLimits(Accuracy::uniformLevel(request.uniform_level()), "uniform_level", limits);
  }
  if (!v1::GlbEncoding_IsValid(request.encoding())) {
    throwInvalidArgument(fmt::format("encoding: unknown value {} (GLB_ENCODING_FLOAT, _QUANTIZED or _MESHOPT)",
                                     int(request.encoding())));
  }
  if (request.has_max_triangles()) {
    int64_t max = request.max_triangles();
    if (max < 0) throwInvalidArgument(fmt::format("max_triangles: must not be negative (got {})", max));
    if (max > limits.maxTriangles) {
      throwResourceExhausted(fmt::format("max_triangles: {} exceeds the server's max_triangles of {}",
                                         max, limits.maxTriangles));
    }
  }
}

TessellationJob planTessellationJob(const v1::TessellateRequest& request,
                                    const MeshMetadata& metadata, const TessellationLimits& limits) {
  TessellationJob job;
  job.meshId = metadata.id;
  job.meshSha256 = metadata.sha256;
  job.eta = request.has_eta() ? request.eta() : kDefaultEta;
  job.maxTriangles = request.has_max_triangles() && request.max_triangles() > 0
                         ? request.max_triangles()
                         : limits.maxTriangles;
  job.encoding = request.encoding() == v1::GLB_ENCODING_QUANTIZED ? GlbEncoding::kQuantized
                 : request.encoding() == v1::GLB_ENCODING_MESHOPT ? GlbEncoding::kMeshopt
                                                                   : GlbEncoding::kFloat;
  if (request.tolerance_case() == v1::TessellateRequest::kPixel) {
    job.camera = checkCamera(request.pixel(), limits);
    job.accuracy = Accuracy::pixel(checkPixelAccuracy(request.pixel(), *job.camera, limits));
  } else if (request.tolerance_case() != v1::TessellateRequest::TOLERANCE_NOT_SET) {
    // ε in model units: the server's limits are checked on it, and the engine gets that value.
    const bool absolute = request.tolerance_case() == v1::TessellateRequest::kAbsolute;
    const Accuracy asked = absolute ? Accuracy::absolute(request.absolute()) : Accuracy::relative(request.relative());
    job.accuracy = Accuracy::absolute(toleranceOnMesh(asked, absolute ? "absolute" : "relative", metadata, limits));
  }
  // A level decides alone, whatever tolerance came with it (checked all the same).
  if (request.has_uniform_level()) {
    job.accuracy = Accuracy::uniformLevel(request.uniform_level());
    job.camera.reset();
  }
  return job;
}

}  // namespace tessera::server
