// One pinhole camera, two types: core's planning camera (double precision, int viewport; it
// sets the per-piece tolerance in pixel-accurate mode, MATH.md §4) and the renderer's (float,
// unsigned viewport, optional near/far planes; gpu/vulkan/camera_math.h). Both look from `eye`
// towards `target` with `up` roughly up and a full vertical field of view `fovYDegrees`; the
// horizontal one follows from width/height. Converting loses only precision and near/far.
#pragma once

#include "core/tessellation_options.h"
#include "gpu/vulkan/render_types.h"

namespace tessera::gpu {

// Near/far are left at 0 (the renderer fits them to the patches). Throws TesseraError
// (kInvalidInput) for a negative viewport side, which has no unsigned counterpart; every other
// check is the renderer's (validateCamera) or core's (validateTessellationOptions).
Camera toGpuCamera(const tessera::Camera& camera);

// Drops near/far. Throws TesseraError (kInvalidInput) for a side above INT_MAX.
tessera::Camera toCoreCamera(const Camera& camera);

}  // namespace tessera::gpu
