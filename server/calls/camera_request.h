// A request's camera (tessera.v1.Camera, in Tessellate's pixel tolerance and in every Render and
// RenderSession camera) turned into core's Camera once: its vectors present, its sides within
// what the caller can draw or plan for, core's rules (validateCamera), and the server's pixel
// budget. `field` names it in messages ("pixel.camera", "cameras[3]").
#pragma once

#include <cstdint>
#include <string_view>

#include "core/request/camera.h"
#include "tessera/v1/tessellation.pb.h"

namespace tessera::server {

// INVALID_ARGUMENT for a missing vector, a side outside [1, maxSide] or a camera core refuses;
// RESOURCE_EXHAUSTED for more than maxImagePixels pixels.
Camera checkedCamera(const tessera::v1::Camera& camera, std::string_view field, int maxSide,
                     int64_t maxImagePixels);

}  // namespace tessera::server
