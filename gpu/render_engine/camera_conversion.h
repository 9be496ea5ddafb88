// The request's camera (core/request/camera.h: double precision, int viewport) as the renderer draws
// through it (gpu/vulkan/render_types.h: float, unsigned viewport, optional near/far planes).
// Converting loses only precision; near and far are left at 0, which the renderer fits to the
// patches.
#pragma once

#include "core/request/camera.h"
#include "gpu/vulkan/render_types.h"

namespace tessera::gpu {

// Expects a camera that passed validateCamera (finite in float, sides >= 1).
Camera toGpuCamera(const tessera::Camera& camera);

}  // namespace tessera::gpu
