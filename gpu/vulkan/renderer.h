// Tessera's Vulkan renderer: draws bicubic Bézier patches offscreen and reads the frame back.
//
//   Renderer r = Renderer::create(DeviceSelection::fromEnvironment());
//   Frame f = r.render(patches, camera, RenderOptions{});
//
// Each patch is tessellated with its own edge levels (interior = max per direction, edges
// stitched D3D11-style, shared edges bit-identical; MATH.md §5), frustum-culled as a whole,
// shaded with Blinn-Phong, and the image is optionally crack-filled (paper §6.2.4). Geometry
// goes through task+mesh shaders when the device has VK_EXT_mesh_shader, else through a compute
// tessellation pass and a vertex-pulling raster pass; both use the same GLSL (shaders/).
//
// render() is synchronous and a Renderer is not thread-safe: give each thread its own, or
// serialize calls. Errors: RenderInputError (bad camera, patches, options),
// RenderUnsupportedError (e.g. the mesh path on a device without it), VulkanError (driver
// failures, with the call and VkResult name).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "gpu/vulkan/device_selection.h"
#include "gpu/vulkan/render_types.h"

namespace tessera::gpu {

class Renderer {
 public:
  static Renderer create(const DeviceSelection& selection);

  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  DeviceInfo info() const;
  bool hasMeshShaders() const;

  Frame render(std::span<const RenderPatch> patches, const Camera& camera,
               const RenderOptions& options);

  // The compute path's tessellation of `patches` (uniformLevel as in RenderOptions), read back
  // to the host instead of drawn; nothing is culled. For meshes (e.g. GPU-side GLB output)
  // and for checking watertightness directly.
  TessellatedMesh tessellate(std::span<const RenderPatch> patches, uint32_t uniformLevel = 0);

  // What the renderer keeps from its frames for the next one: the render targets (sized by the
  // last frame's pixels, 44 bytes a pixel on lavapipe), the geometry buffers (by its largest
  // batch) and the patch buffer. releaseFrameMemory() frees them; the next frame makes them again.
  // A server calls it after a large frame, so one 8192 x 8192 frame does not hold ~3 GB until
  // the next one (server/render/render_vulkan_backend.cpp).
  uint64_t frameMemoryBytes() const;
  void releaseFrameMemory();

  // Validation-layer messages since the last call; empty unless validation was requested and
  // the layer is installed.
  std::vector<std::string> takeValidationMessages();

 private:
  struct Impl;
  explicit Renderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace tessera::gpu
