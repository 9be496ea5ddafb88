#include "server/http/http_query.h"

#include <fmt/format.h>

#include <optional>

#include "core/request/camera_text.h"
#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

void setVector(const QueryParameters& query, const char* name, const char* fallback, v1::Vec3& out) {
  const std::optional<std::string> text = queryParameter(query, name);
  if (!text && !fallback) throwInvalidArgument(fmt::format("query parameter {}: is required (X,Y,Z)", name));
  const std::string typed = text.value_or(fallback);
  const std::optional<TypedVector> v = parseXyz(typed);
  if (!v) throwInvalidArgument(fmt::format("query parameter {}: expects X,Y,Z, got {}", name, quoteForMessage(typed)));
  out.set_x(v->x), out.set_y(v->y), out.set_z(v->z);
}

// The camera every frame and every pixel-accurate tessellation needs.
v1::Camera cameraFromQuery(const QueryParameters& query) {
  v1::Camera camera;
  setVector(query, "eye", nullptr, *camera.mutable_eye());
  setVector(query, "target", nullptr, *camera.mutable_target());
  setVector(query, "up", "0,1,0", *camera.mutable_up());
  camera.set_fov_y_deg(queryNumber<double>(query, "fov").value_or(45.0));
  const std::string size = queryParameter(query, "size").value_or("1920x1080");
  const std::optional<TypedSize> parsed = parseWxH(size);
  if (!parsed) throwInvalidArgument(fmt::format("query parameter size: expects WIDTHxHEIGHT, got {}", quoteForMessage(size)));
  camera.set_width(parsed->width);
  camera.set_height(parsed->height);
  return camera;
}

v1::GlbEncoding encodingFromQuery(const QueryParameters& query) {
  const std::string name = queryParameter(query, "encoding").value_or("float");
  if (name == "float") return v1::GLB_ENCODING_FLOAT;
  if (name == "quantized") return v1::GLB_ENCODING_QUANTIZED;
  if (name == "meshopt") return v1::GLB_ENCODING_MESHOPT;
  throwInvalidArgument(fmt::format("query parameter encoding: expects float, quantized or meshopt, got {}",
                                   quoteForMessage(name)));
}

std::optional<bool> flag(const QueryParameters& query, const char* name) {
  const std::optional<std::string> text = queryParameter(query, name);
  if (!text) return std::nullopt;
  if (*text == "true" || *text == "1") return true;
  if (*text == "false" || *text == "0") return false;
  throwInvalidArgument(fmt::format("query parameter {}: expects true or false, got {}", name, quoteForMessage(*text)));
}

}  // namespace

std::optional<std::string> queryParameter(const QueryParameters& query, const char* name) {
  auto found = query.find(name);
  if (found == query.end()) return std::nullopt;
  return found->second;
}

void throwNotANumber(const char* name, const std::string& text) {
  throwInvalidArgument(fmt::format("query parameter {}: expects a number, got {}", name, quoteForMessage(text)));
}

void checkQueryParameters(const QueryParameters& query, std::initializer_list<const char*> known) {
  for (auto it = query.begin(); it != query.end(); it = query.upper_bound(it->first)) {
    const std::string& name = it->first;
    bool listed = name == "timeout_ms";
    std::string names;
    for (const char* k : known) {
      listed = listed || name == k;
      names += names.empty() ? k : fmt::format(", {}", k);
    }
    if (!listed) {
      throwInvalidArgument(fmt::format("query parameter {} is unknown here (known: {}, timeout_ms)",
                                       quoteForMessage(name), names));
    }
    if (query.count(name) > 1) throwInvalidArgument(fmt::format("query parameter {}: given more than once", name));
  }
}

v1::TessellateRequest tessellateRequestFromQuery(const std::string& meshId, const QueryParameters& query) {
  checkQueryParameters(query, {"relative", "absolute", "eye", "target", "up", "fov", "size", "pixel_accuracy",
                               "uniform_level", "eta", "max_triangles", "encoding"});
  v1::TessellateRequest request;
  request.set_name("meshes/" + meshId);
  const int tolerances = int(query.count("relative")) + int(query.count("absolute")) +
                         int(query.count("eye") || query.count("target"));
  if (tolerances > 1) {
    throwInvalidArgument("query: give one of relative, absolute or a camera (eye and target), not several");
  }
  if (auto relative = queryNumber<double>(query, "relative")) request.set_relative(*relative);
  if (auto absolute = queryNumber<double>(query, "absolute")) request.set_absolute(*absolute);
  if (query.count("eye") || query.count("target")) {
    *request.mutable_pixel()->mutable_camera() = cameraFromQuery(query);
    if (auto pixels = queryNumber<double>(query, "pixel_accuracy")) request.mutable_pixel()->set_pixel_accuracy(*pixels);
  } else {
    for (const char* cameraOnly : {"up", "fov", "size", "pixel_accuracy"}) {
      if (query.count(cameraOnly)) {
        throwInvalidArgument(fmt::format("query parameter {}: belongs to a camera (eye and target)", cameraOnly));
      }
    }
  }
  if (auto level = queryNumber<int32_t>(query, "uniform_level")) request.set_uniform_level(*level);
  if (auto eta = queryNumber<double>(query, "eta")) request.set_eta(*eta);
  if (auto max = queryNumber<int64_t>(query, "max_triangles")) request.set_max_triangles(*max);
  request.set_encoding(encodingFromQuery(query));
  return request;
}

v1::RenderRequest renderRequestFromQuery(const std::string& meshId, const QueryParameters& query,
                                         v1::ImageFormat format) {
  checkQueryParameters(query, {"eye", "target", "up", "fov", "size", "pixel_accuracy", "absolute_tolerance",
                               "uniform_level", "eta", "max_triangles", "crack_filling", "jpeg_quality"});
  v1::RenderRequest request;
  request.set_name("meshes/" + meshId);
  *request.add_cameras() = cameraFromQuery(query);
  v1::RenderSettings& settings = *request.mutable_settings();
  const int accuracies = int(query.count("pixel_accuracy") + query.count("absolute_tolerance") + query.count("uniform_level"));
  if (accuracies > 1) {
    throwInvalidArgument("query: give one of pixel_accuracy, absolute_tolerance or uniform_level, not several");
  }
  if (auto pixels = queryNumber<double>(query, "pixel_accuracy")) settings.set_pixel_accuracy(*pixels);
  if (auto absolute = queryNumber<double>(query, "absolute_tolerance")) settings.set_absolute_tolerance(*absolute);
  if (auto level = queryNumber<int32_t>(query, "uniform_level")) settings.set_uniform_level(*level);
  if (auto eta = queryNumber<double>(query, "eta")) settings.set_eta(*eta);
  if (auto max = queryNumber<int64_t>(query, "max_triangles")) settings.set_max_triangles(*max);
  if (auto crackFilling = flag(query, "crack_filling")) settings.set_crack_filling(*crackFilling);
  if (auto quality = queryNumber<int32_t>(query, "jpeg_quality")) settings.set_jpeg_quality(*quality);
  settings.set_format(format);
  return request;
}

}  // namespace tessera::server
