#include "server/tessellate_request.h"

#include <fmt/format.h>

#include <cmath>

#include "server/status_error.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

constexpr double kDefaultEta = 0.5;
constexpr double kDefaultPixelAccuracy = 0.5;
constexpr int kMaxViewportSide = 16384;

Vec3d requireVec3(bool present, const v1::Vec3& v, const char* field) {
  if (!present) throwInvalidArgument(fmt::format("{}: is required", field));
  if (!std::isfinite(v.x()) || !std::isfinite(v.y()) || !std::isfinite(v.z())) {
    throwInvalidArgument(fmt::format("{}: coordinates must be finite", field));
  }
  return Vec3d(v.x(), v.y(), v.z());
}

CameraSpec checkCamera(const v1::PixelTolerance& pixel, const TessellationLimits& limits) {
  if (!pixel.has_camera()) throwInvalidArgument("pixel.camera: is required");
  const v1::Camera& c = pixel.camera();
  CameraSpec camera;
  camera.eye = requireVec3(c.has_eye(), c.eye(), "pixel.camera.eye");
  camera.target = requireVec3(c.has_target(), c.target(), "pixel.camera.target");
  camera.up = requireVec3(c.has_up(), c.up(), "pixel.camera.up");
  Vec3d view = camera.target - camera.eye;
  double viewLength = length(view);
  if (!(viewLength > 0) || !std::isfinite(viewLength)) {
    throwInvalidArgument("pixel.camera: eye and target must be distinct points");
  }
  double upLength = length(camera.up);
  // sin of the angle between up and the view direction; ~0 leaves the camera's roll undefined.
  if (!(upLength > 0) || length(cross(view, camera.up)) <= 1e-9 * viewLength * upLength) {
    throwInvalidArgument("pixel.camera.up: must be non-zero and not parallel to target - eye");
  }
  camera.fovYDeg = c.fov_y_deg();
  if (!std::isfinite(camera.fovYDeg) || camera.fovYDeg <= 0 || camera.fovYDeg >= 180) {
    throwInvalidArgument(fmt::format("pixel.camera.fov_y_deg: must be in (0, 180) degrees (got {})",
                                     camera.fovYDeg));
  }
  camera.width = c.width();
  camera.height = c.height();
  for (auto [value, field] : {std::pair{c.width(), "pixel.camera.width"},
                              std::pair{c.height(), "pixel.camera.height"}}) {
    if (value < 1 || value > kMaxViewportSide) {
      throwInvalidArgument(
          fmt::format("{}: must be in [1, {}] pixels (got {})", field, kMaxViewportSide, value));
    }
  }
  if (int64_t(c.width()) * c.height() > limits.maxImagePixels) {
    throwResourceExhausted(fmt::format("pixel.camera: {}x{} pixels exceeds the server's "
                                       "max_image_pixels of {}",
                                       c.width(), c.height(), limits.maxImagePixels));
  }
  return camera;
}

double checkPixelAccuracy(const v1::PixelTolerance& pixel, const CameraSpec& camera,
                          const TessellationLimits& limits) {
  double accuracy = pixel.has_pixel_accuracy() ? pixel.pixel_accuracy() : kDefaultPixelAccuracy;
  requirePositiveFinite(accuracy, "pixel.pixel_accuracy");
  int largestSide = std::max(camera.width, camera.height);
  if (accuracy > largestSide) {
    throwInvalidArgument(fmt::format("pixel.pixel_accuracy: {} pixels is larger than the {}x{} "
                                     "viewport",
                                     accuracy, camera.width, camera.height));
  }
  if (accuracy < limits.minPixelAccuracy) {
    throwResourceExhausted(fmt::format("pixel.pixel_accuracy: {} is finer than the server's "
                                       "min_pixel_accuracy of {}",
                                       accuracy, limits.minPixelAccuracy));
  }
  return accuracy;
}

void checkTolerance(const v1::TessellateRequest& request, const TessellationLimits& limits) {
  switch (request.tolerance_case()) {
    case v1::TessellateRequest::kAbsolute:
      requirePositiveFinite(request.absolute(), "absolute");
      return;
    case v1::TessellateRequest::kRelative:
      requirePositiveFinite(request.relative(), "relative");
      if (request.relative() >= 1) {
        throwInvalidArgument(fmt::format("relative: must be below 1, the whole bounding-box "
                                         "diagonal (got {})",
                                         request.relative()));
      }
      return;
    case v1::TessellateRequest::kPixel: {
      CameraSpec camera = checkCamera(request.pixel(), limits);
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
    int level = request.uniform_level();
    if (level < 1 || level > limits.maxUniformLevel) {
      throwInvalidArgument(fmt::format("uniform_level: must be in [1, {}] (got {})",
                                       limits.maxUniformLevel, level));
    }
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
  job.uniformLevel = request.has_uniform_level() ? request.uniform_level() : 0;
  job.maxTriangles = request.has_max_triangles() && request.max_triangles() > 0
                         ? request.max_triangles()
                         : limits.maxTriangles;
  job.encoding = request.encoding() == v1::GLB_ENCODING_QUANTIZED ? GlbEncoding::kQuantized
                 : request.encoding() == v1::GLB_ENCODING_MESHOPT ? GlbEncoding::kMeshopt
                                                                   : GlbEncoding::kFloat;
  const double diagonal = metadata.boundsDiagonal();
  if (request.tolerance_case() == v1::TessellateRequest::TOLERANCE_NOT_SET) {
    job.toleranceMode = ToleranceMode::kNone;
    return job;
  }
  if (request.tolerance_case() == v1::TessellateRequest::kPixel) {
    job.toleranceMode = ToleranceMode::kPixel;
    job.camera = checkCamera(request.pixel(), limits);
    job.pixelAccuracy = checkPixelAccuracy(request.pixel(), *job.camera, limits);
    return job;
  }
  if (!(diagonal > 0)) {
    throwStatus(grpc::StatusCode::FAILED_PRECONDITION,
                fmt::format("mesh {} has an empty bounding box, so a tolerance has no scale",
                            metadata.id));
  }
  const bool absolute = request.tolerance_case() == v1::TessellateRequest::kAbsolute;
  job.toleranceMode = absolute ? ToleranceMode::kAbsolute : ToleranceMode::kRelative;
  job.tolerance = absolute ? request.absolute() : request.relative() * diagonal;
  const char* field = absolute ? "absolute" : "relative";
  if (absolute && job.tolerance > diagonal) {
    throwInvalidArgument(fmt::format("absolute: {} is larger than the mesh's bounding-box diagonal "
                                     "({})",
                                     job.tolerance, diagonal));
  }
  if (job.tolerance < limits.minRelativeTolerance * diagonal) {
    throwResourceExhausted(fmt::format("{}: a tolerance of {} ({} of the bounding-box diagonal) is "
                                       "finer than the server's min_relative_tolerance of {}",
                                       field, job.tolerance, job.tolerance / diagonal,
                                       limits.minRelativeTolerance));
  }
  return job;
}

}  // namespace tessera::server
