// The front door's query parameters as the gRPC requests they stand for, so that an HTTP client
// gets exactly the API's checks, limits and messages (the services check the requests; this
// file only reads them). A parameter that is malformed, repeated or unknown to the endpoint is an
// INVALID_ARGUMENT (StatusError) naming it.
//
// tessellation.glb: one of relative=E, absolute=E, or a camera (eye=X,Y,Z & target=X,Y,Z, with
// up=X,Y,Z (0,1,0), fov=DEGREES (45), size=WxH (1920x1080), pixel_accuracy=PX) for pixel
// accuracy; uniform_level=P (alone or with a tolerance); eta, max_triangles,
// encoding=float|quantized|meshopt.
// frame.png / frame.jpg: the camera (eye and target required) and one of pixel_accuracy,
// absolute_tolerance, uniform_level; eta, max_triangles, crack_filling=true|false,
// jpeg_quality.
// Every endpoint also takes timeout_ms, the call's deadline (read by the front door itself).
#pragma once

#include <charconv>
#include <map>
#include <optional>
#include <string>

#include "tessera/v1/render.pb.h"
#include "tessera/v1/tessellation.pb.h"

namespace tessera::server {

using QueryParameters = std::multimap<std::string, std::string>;

tessera::v1::TessellateRequest tessellateRequestFromQuery(const std::string& meshId,
                                                          const QueryParameters& query);

tessera::v1::RenderRequest renderRequestFromQuery(const std::string& meshId, const QueryParameters& query,
                                                  tessera::v1::ImageFormat format);

// The parameter's value, if given.
std::optional<std::string> queryParameter(const QueryParameters& query, const char* name);

[[noreturn]] void throwNotANumber(const char* name, const std::string& text);

// The parameter as a number, if given; INVALID_ARGUMENT naming it when it is not one.
template <typename Number>
std::optional<Number> queryNumber(const QueryParameters& query, const char* name) {
  const std::optional<std::string> text = queryParameter(query, name);
  if (!text) return std::nullopt;
  Number value{};
  const char* end = text->data() + text->size();
  auto [stop, error] = std::from_chars(text->data(), end, value);
  if (error != std::errc() || stop != end) throwNotANumber(name, *text);
  return value;
}

// Refuses a parameter outside `known` (plus timeout_ms) or given twice.
void checkQueryParameters(const QueryParameters& query, std::initializer_list<const char*> known);

}  // namespace tessera::server
