#include "server/render/render_request.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "server/calls/camera_request.h"
#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

constexpr double kDefaultPixelAccuracy = 0.5;
constexpr double kDefaultEta = 0.5;

Accuracy checkAccuracy(const v1::RenderSettings& s, std::string_view field, const TessellationLimits& limits) {
  Accuracy accuracy;
  std::string where;
  switch (s.accuracy_case()) {
    case v1::RenderSettings::ACCURACY_NOT_SET:
      accuracy = Accuracy::pixel(kDefaultPixelAccuracy);
      where = fmt::format("{}.pixel_accuracy", field);
      break;
    case v1::RenderSettings::kPixelAccuracy:
      accuracy = Accuracy::pixel(s.pixel_accuracy());
      where = fmt::format("{}.pixel_accuracy", field);
      break;
    case v1::RenderSettings::kAbsoluteTolerance:
      accuracy = Accuracy::absolute(s.absolute_tolerance());
      where = fmt::format("{}.absolute_tolerance", field);
      break;
    case v1::RenderSettings::kUniformLevel:
      accuracy = Accuracy::uniformLevel(s.uniform_level());
      where = fmt::format("{}.uniform_level", field);
      break;
  }
  checkWithCore([&] { validateAccuracy(accuracy, where); });
  checkAccuracyLimits(accuracy, where, limits);
  return accuracy;
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
  frame.accuracy = checkAccuracy(s, field, limits);
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
  if (settings.accuracy.mode != Accuracy::Mode::kAbsolute) return;
  toleranceOnMesh(settings.accuracy, fmt::format("{}.absolute_tolerance", field), metadata, limits);
}

Camera checkRenderCamera(const v1::Camera& c, std::string_view field,
                         const FrameSettings& settings, const TessellationLimits& limits) {
  const Camera camera = checkedCamera(c, field, kMaxRenderViewportSide, limits.maxImagePixels);
  if (settings.accuracy.pixelAccurate()) {
    checkWithCore([&] { validatePixelsForViewport(settings.accuracy.pixels, camera.width, camera.height, field); });
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
