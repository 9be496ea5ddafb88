#include "server/tessellation/tessellate_request.h"

#include <fmt/format.h>

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

// The accuracy as asked (a tolerance still absolute or relative: it waits for the mesh), with the
// camera a pixel accuracy is for. A level decides alone, whatever tolerance came with it
// (checked all the same).
void checkAccuracy(const v1::TessellateRequest& request, const TessellationLimits& limits, TessellationJob& job) {
  switch (request.tolerance_case()) {
    case v1::TessellateRequest::kAbsolute:
      checkWithCore([&] { validateTolerance(request.absolute(), false, "absolute"); });
      job.accuracy = Accuracy::absolute(request.absolute());
      break;
    case v1::TessellateRequest::kRelative:
      checkWithCore([&] { validateTolerance(request.relative(), true, "relative"); });
      job.accuracy = Accuracy::relative(request.relative());
      break;
    case v1::TessellateRequest::kPixel:
      job.camera = checkCamera(request.pixel(), limits);
      job.accuracy = Accuracy::pixel(checkPixelAccuracy(request.pixel(), *job.camera, limits));
      break;
    case v1::TessellateRequest::TOLERANCE_NOT_SET:
      if (!request.has_uniform_level()) {
        throwInvalidArgument(
            "tolerance: one of absolute, relative or pixel is required (or a uniform_level)");
      }
      break;
  }
  if (request.has_uniform_level()) {
    checkWithCore([&] { validateUniformLevel(request.uniform_level(), "uniform_level"); });
    job.accuracy = Accuracy::uniformLevel(request.uniform_level());
    checkAccuracyLimits(job.accuracy, "uniform_level", limits);
    job.camera.reset();
  }
}

}  // namespace

TessellationJob checkTessellateRequest(const v1::TessellateRequest& request, const TessellationLimits& limits) {
  TessellationJob job;
  checkAccuracy(request, limits, job);
  job.eta = request.has_eta() ? request.eta() : kDefaultEta;
  checkWithCore([&] { validateEta(job.eta, "eta"); });
  if (!v1::GlbEncoding_IsValid(request.encoding())) {
    throwInvalidArgument(fmt::format("encoding: unknown value {} (GLB_ENCODING_FLOAT, _QUANTIZED or _MESHOPT)",
                                     int(request.encoding())));
  }
  job.encoding = request.encoding() == v1::GLB_ENCODING_QUANTIZED ? GlbEncoding::kQuantized
                 : request.encoding() == v1::GLB_ENCODING_MESHOPT ? GlbEncoding::kMeshopt
                                                                   : GlbEncoding::kFloat;
  job.maxTriangles = limits.maxTriangles;
  if (request.has_max_triangles()) {
    int64_t max = request.max_triangles();
    if (max < 0) throwInvalidArgument(fmt::format("max_triangles: must not be negative (got {})", max));
    if (max > limits.maxTriangles) {
      throwResourceExhausted(fmt::format("max_triangles: {} exceeds the server's max_triangles of {}",
                                         max, limits.maxTriangles));
    }
    if (max > 0) job.maxTriangles = max;
  }
  return job;
}

void placeOnMesh(TessellationJob& job, const MeshMetadata& metadata, const TessellationLimits& limits) {
  job.meshId = metadata.id;
  job.meshSha256 = metadata.sha256;
  const Accuracy::Mode mode = job.accuracy.mode;
  if (mode != Accuracy::Mode::kAbsolute && mode != Accuracy::Mode::kRelative) return;
  // ε in model units: the server's limits are checked on it, and the engine gets that value.
  const char* field = mode == Accuracy::Mode::kAbsolute ? "absolute" : "relative";
  job.accuracy = Accuracy::absolute(toleranceOnMesh(job.accuracy, field, metadata, limits));
}

void checkOnMesh(const TessellationJob& job, const ControlMesh& mesh, const TessellationLimits& limits) {
  if (job.camera) checkPixelsOnMesh(job.accuracy, *job.camera, mesh, "pixel", limits);
}

}  // namespace tessera::server
