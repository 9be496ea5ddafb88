// Checks the parts of Render and RenderSession requests (render.proto) against the API's rules
// and the server's budgets, and turns them into FrameSettings and Cameras. Refusals name the
// field, with the camera's index or sequence number: INVALID_ARGUMENT for values that make no
// sense, RESOURCE_EXHAUSTED for sensible values past a budget (as tessellate_request.h does).
#pragma once

#include <string_view>

#include "server/render/frame_encoder.h"
#include "server/meshes/mesh_metadata.h"
#include "server/render/render_backend.h"
#include "server/calls/accuracy_limits.h"
#include "tessera/v1/render.pb.h"

namespace tessera::server {

// The API's limits (render.proto).
inline constexpr int kMaxCamerasPerRequest = 64;
inline constexpr int kMaxRenderViewportSide = 8192;  // the renderer's target limit
struct CheckedRenderSettings {
  FrameSettings frame;
  EncodingSettings encoding;
};

// Everything that needs neither the mesh nor a camera. `field` prefixes the messages
// ("settings", "start.settings").
CheckedRenderSettings checkRenderSettings(const tessera::v1::RenderSettings& settings,
                                          std::string_view field, const TessellationLimits& limits);

// The checks that need the mesh: an absolute tolerance against its bounding-box diagonal.
void checkSettingsForMesh(const FrameSettings& settings, std::string_view field,
                          const MeshMetadata& metadata, const TessellationLimits& limits);

// One camera, named `field` in messages ("cameras[3]", "camera (sequence 7)"), checked as the
// renderer will see it (single precision) and against the pixel accuracy of `settings`.
Camera checkRenderCamera(const tessera::v1::Camera& camera, std::string_view field,
                             const FrameSettings& settings, const TessellationLimits& limits);

tessera::v1::ImageFormat toProto(FrameFormat format);

}  // namespace tessera::server
