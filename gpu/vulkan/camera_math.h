// Camera validation and the view-projection matrix (right-handed view space looking down -z,
// Vulkan clip space: depth in [0,1], framebuffer row 0 at the top). Near and far planes not
// given by the caller are fitted to the bounding sphere of the patches' control points, which
// contains the surfaces (convex hull property), so nothing visible is clipped by them.
#pragma once

#include <array>
#include <span>

#include "gpu/vulkan/render_types.h"

namespace tessera::gpu {

struct SceneBounds {
  Vec3 min{0.0f, 0.0f, 0.0f};
  Vec3 max{0.0f, 0.0f, 0.0f};
  bool empty = true;
};

struct ViewProjection {
  std::array<float, 16> matrix{};  // column-major, as GLSL's mat4
  float nearPlane = 0.0f;
  float farPlane = 0.0f;
};

// Throws RenderInputError naming the bad field: non-finite values, eye == target, up parallel
// to the view direction, fov outside (0, 180), a side of 0 or above kMaxTargetSize, or
// explicit near/far planes that are not 0 < near < far.
void validateCamera(const Camera& camera);

SceneBounds boundsOf(std::span<const RenderPatch> patches);

// The camera must have passed validateCamera.
ViewProjection buildViewProjection(const Camera& camera, const SceneBounds& bounds);

}  // namespace tessera::gpu
