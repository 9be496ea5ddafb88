#include "server/render_request.h"

#include <fmt/format.h>

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "server/status_error.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

constexpr double kDefaultPixelAccuracy = 0.5;
constexpr double kDefaultEta = 0.5;
// The renderer's own test (gpu/vulkan/camera_math.cpp) on the sine between up and the view
// direction; checking the same bound here keeps its error from ever being the one users see.
constexpr double kMinUpSine = 1e-6;

// The renderer works in single precision: a double that is finite but beyond float's range
// would become infinite there.
bool fitsFloat(double value) {
  return std::isfinite(value) && std::fabs(value) <= FLT_MAX;
}

Vec3d requireVec3(bool present, const v1::Vec3& v, std::string_view field) {
  if (!present) throwInvalidArgument(fmt::format("{}: is required", field));
  if (!fitsFloat(v.x()) || !fitsFloat(v.y()) || !fitsFloat(v.z())) {
    throwInvalidArgument(
        fmt::format("{}: coordinates must be finite single-precision numbers "
                    "(got {}, {}, {})",
                    field, v.x(), v.y(), v.z()));
  }
  return Vec3d(v.x(), v.y(), v.z());
}

// As the renderer will see it: rounded to float.
Vec3d asFloat(const Vec3d& v) {
  return Vec3d(Vec3(v));
}

void checkViewGeometry(const CameraSpec& camera, std::string_view field) {
  Vec3d view = asFloat(camera.target) - asFloat(camera.eye);
  double viewLength = length(view);
  if (!(viewLength > 0) || !(length(camera.target - camera.eye) > 0)) {
    throwInvalidArgument(fmt::format("{}: eye and target must be distinct points", field));
  }
  Vec3d up = asFloat(camera.up);
  double upLength = length(up);
  if (!(upLength > 0)) throwInvalidArgument(fmt::format("{}.up: must be non-zero", field));
  if (!(length(cross(view, up)) > kMinUpSine * viewLength * upLength)) {
    throwInvalidArgument(fmt::format("{}.up: must not be parallel to target - eye", field));
  }
}

void checkViewport(const v1::Camera& c, std::string_view field, const TessellationLimits& limits) {
  for (auto [value, name] : {std::pair{c.width(), "width"}, std::pair{c.height(), "height"}}) {
    if (value < 1 || value > kMaxRenderViewportSide) {
      throwInvalidArgument(fmt::format("{}.{}: must be in [1, {}] pixels (got {})", field, name,
                                       kMaxRenderViewportSide, value));
    }
  }
  if (int64_t(c.width()) * c.height() > limits.maxImagePixels) {
    throwResourceExhausted(
        fmt::format("{}: {}x{} pixels exceeds the server's max_image_pixels "
                    "of {}",
                    field, c.width(), c.height(), limits.maxImagePixels));
  }
}

void checkAccuracy(const v1::RenderSettings& s, std::string_view field,
                   const TessellationLimits& limits, FrameSettings& out) {
  switch (s.accuracy_case()) {
    case v1::RenderSettings::ACCURACY_NOT_SET:
      out.accuracy = FrameAccuracy::kPixel;
      out.pixelAccuracy = kDefaultPixelAccuracy;
      break;
    case v1::RenderSettings::kPixelAccuracy:
      out.accuracy = FrameAccuracy::kPixel;
      out.pixelAccuracy = s.pixel_accuracy();
      requirePositiveFinite(out.pixelAccuracy, fmt::format("{}.pixel_accuracy", field));
      break;
    case v1::RenderSettings::kAbsoluteTolerance:
      out.accuracy = FrameAccuracy::kAbsolute;
      out.tolerance = s.absolute_tolerance();
      requirePositiveFinite(out.tolerance, fmt::format("{}.absolute_tolerance", field));
      return;
    case v1::RenderSettings::kUniformLevel:
      out.accuracy = FrameAccuracy::kUniform;
      out.uniformLevel = s.uniform_level();
      if (out.uniformLevel < 1 || out.uniformLevel > limits.maxUniformLevel) {
        throwInvalidArgument(fmt::format("{}.uniform_level: must be in [1, {}] (got {})", field,
                                         limits.maxUniformLevel, out.uniformLevel));
      }
      return;
  }
  if (out.pixelAccuracy < limits.minPixelAccuracy) {
    throwResourceExhausted(
        fmt::format("{}.pixel_accuracy: {} is finer than the server's "
                    "min_pixel_accuracy of {}",
                    field, out.pixelAccuracy, limits.minPixelAccuracy));
  }
}

EncodingSettings checkEncoding(const v1::RenderSettings& s, std::string_view field) {
  EncodingSettings out;
  switch (s.format()) {
    case v1::IMAGE_FORMAT_UNSPECIFIED:
    case v1::IMAGE_FORMAT_PNG:
      out.format = FrameFormat::kPng;
      break;
    case v1::IMAGE_FORMAT_JPEG:
      out.format = FrameFormat::kJpeg;
      break;
    case v1::IMAGE_FORMAT_EXR:
      out.format = FrameFormat::kExr;
      break;
    case v1::IMAGE_FORMAT_RAW_RGBA:
      out.format = FrameFormat::kRawRgba;
      break;
    default:
      throwInvalidArgument(
          fmt::format("{}.format: unknown image format {}", field, static_cast<int>(s.format())));
  }
  if (s.has_jpeg_quality()) {
    if (out.format != FrameFormat::kJpeg) {
      throwInvalidArgument(
          fmt::format("{}.jpeg_quality: applies to IMAGE_FORMAT_JPEG only", field));
    }
    out.jpegQuality = s.jpeg_quality();
    if (out.jpegQuality < 1 || out.jpegQuality > 100) {
      throwInvalidArgument(
          fmt::format("{}.jpeg_quality: must be in [1, 100] (got {})", field, out.jpegQuality));
    }
  }
  return out;
}

}  // namespace

CheckedRenderSettings checkRenderSettings(const v1::RenderSettings& s, std::string_view field,
                                          const TessellationLimits& limits) {
  CheckedRenderSettings out;
  FrameSettings& frame = out.frame;
  checkAccuracy(s, field, limits, frame);
  frame.eta = s.has_eta() ? s.eta() : kDefaultEta;
  if (!std::isfinite(frame.eta) || frame.eta <= 0 || frame.eta >= 1) {
    throwInvalidArgument(fmt::format("{}.eta: must be in (0, 1) (got {})", field, frame.eta));
  }
  frame.maxTriangles = limits.maxTriangles;
  if (s.has_max_triangles()) {
    int64_t max = s.max_triangles();
    if (max < 0) {
      throwInvalidArgument(
          fmt::format("{}.max_triangles: must not be negative (got {})", field, max));
    }
    if (max > limits.maxTriangles) {
      throwResourceExhausted(
          fmt::format("{}.max_triangles: {} exceeds the server's "
                      "max_triangles of {}",
                      field, max, limits.maxTriangles));
    }
    if (max > 0) frame.maxTriangles = max;
  }
  frame.crackFilling = !s.has_crack_filling() || s.crack_filling();
  out.encoding = checkEncoding(s, field);
  return out;
}

void checkSettingsForMesh(const FrameSettings& settings, std::string_view field,
                          const MeshMetadata& metadata, const TessellationLimits& limits) {
  if (settings.accuracy != FrameAccuracy::kAbsolute) return;
  const double diagonal = metadata.boundsDiagonal();
  if (!(diagonal > 0)) {
    throwStatus(
        grpc::StatusCode::FAILED_PRECONDITION,
        fmt::format("mesh {} has an empty bounding box, so a tolerance has no scale", metadata.id));
  }
  if (settings.tolerance > diagonal) {
    throwInvalidArgument(
        fmt::format("{}.absolute_tolerance: {} is larger than the mesh's "
                    "bounding-box diagonal ({})",
                    field, settings.tolerance, diagonal));
  }
  if (settings.tolerance < limits.minRelativeTolerance * diagonal) {
    throwResourceExhausted(fmt::format(
        "{}.absolute_tolerance: {} ({} of the bounding-box "
        "diagonal) is finer than the server's "
        "min_relative_tolerance of {}",
        field, settings.tolerance, settings.tolerance / diagonal, limits.minRelativeTolerance));
  }
}

CameraSpec checkRenderCamera(const v1::Camera& c, std::string_view field,
                             const FrameSettings& settings, const TessellationLimits& limits) {
  CameraSpec camera;
  camera.eye = requireVec3(c.has_eye(), c.eye(), fmt::format("{}.eye", field));
  camera.target = requireVec3(c.has_target(), c.target(), fmt::format("{}.target", field));
  camera.up = requireVec3(c.has_up(), c.up(), fmt::format("{}.up", field));
  checkViewGeometry(camera, field);
  camera.fovYDeg = c.fov_y_deg();
  float fov = static_cast<float>(camera.fovYDeg);
  if (!std::isfinite(camera.fovYDeg) || !(fov > 0.0f) || !(fov < 180.0f)) {
    throwInvalidArgument(
        fmt::format("{}.fov_y_deg: must be in (0, 180) degrees (got {})", field, camera.fovYDeg));
  }
  checkViewport(c, field, limits);
  camera.width = c.width();
  camera.height = c.height();
  if (settings.accuracy == FrameAccuracy::kPixel &&
      settings.pixelAccuracy > std::max(camera.width, camera.height)) {
    throwInvalidArgument(
        fmt::format("{}: a pixel accuracy of {} pixels is larger than its {}x{} "
                    "viewport",
                    field, settings.pixelAccuracy, camera.width, camera.height));
  }
  return camera;
}

v1::ImageFormat toProto(FrameFormat format) {
  switch (format) {
    case FrameFormat::kPng:
      return v1::IMAGE_FORMAT_PNG;
    case FrameFormat::kJpeg:
      return v1::IMAGE_FORMAT_JPEG;
    case FrameFormat::kExr:
      return v1::IMAGE_FORMAT_EXR;
    case FrameFormat::kRawRgba:
      return v1::IMAGE_FORMAT_RAW_RGBA;
  }
  return v1::IMAGE_FORMAT_UNSPECIFIED;
}

}  // namespace tessera::server
