// A frame of a Catmull-Clark surface, the paper's way (§5-6): plan on the CPU (a FAS depth per
// extraordinary ring and an FMM86 level per Bézier piece, core/uniform/tessellation_plan.h), hand the
// pieces to the Vulkan renderer as bicubic patches, tessellate, rasterise with Blinn-Phong, and
// repair the cracks between pieces in image space (§6.2.3-6.2.4).
//
//   FrameEngine engine = FrameEngine::create(DeviceSelection::fromEnvironment());
//   FrameRequest request;
//   request.camera = {.eye = {0, 0, 5}, .target = {0, 0, 0}, .width = 1920, .height = 1080};
//   EngineFrame frame = engine.render(buildPatchSet(mesh), request);
//
// Accuracy (core/request/accuracy.h): pixel-accurate (ε is `pixels` projected back to object space per
// piece and per ring for the request's camera, MATH.md §4), a tolerance in object space or as a
// fraction of the diagonal, or the paper's uniform level p (Table 2). Nothing is cached between frames; the engine owns one
// Renderer and, like it, is not thread-safe.
//
// Errors: a bad request (camera with NaN, a side of 0 or above 8192 pixels, a bad tolerance,
// η or level) is a TesseraError (kInvalidInput) raised before any work; a frame over the
// triangle budget a TesseraError (kLimitExceeded) raised before anything is split or
// uploaded. Device failures come from the renderer (VulkanError, RenderUnsupportedError, and
// RenderInputError when the device cannot read that many patches in one frame).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/request/tessellation_options.h"
#include "core/rings/patch_set.h"
#include "core/uniform/tessellation_plan.h"
#include "gpu/vulkan/device_selection.h"
#include "gpu/vulkan/render_types.h"
#include "gpu/vulkan/renderer.h"

namespace tessera::gpu {

struct FrameRequest {
  tessera::Camera camera;  // eye, target, up, vertical fov, viewport (1..8192 per side)
  // A uniform level p draws every piece at p halved per subdivision level (levels above 64 are
  // split); a pixel accuracy is for `camera`.
  Accuracy accuracy = Accuracy::pixel(0.5);
  double eta = 0.5;                   // share of ε for the innermost Bézier approximation (§5.1)
  int64_t maxTriangles = 20'000'000;  // budget for the triangles the frame would draw
  // Path, crack filling, background, light and material. Its uniformLevel must stay 0: the
  // engine sets every patch's levels (ask for Accuracy::uniformLevel instead).
  RenderOptions render;
  // Called with the triangles the frame will draw once they are counted (within maxTriangles),
  // before the render patches are made; may throw. A server reserves their memory here.
  std::function<void(int64_t triangles)> beforeDrawing;
};

// Milliseconds. GPU stages come from the renderer (gpu/vulkan StageTimings: timestamps on
// GPUs; host-timed separate submissions on CPU devices such as lavapipe).
struct FrameTimings {
  double planMs = 0;           // planTessellation: ring depths, pieces, levels (CPU)
  double patchesMs = 0;        // pieces → render patches: frustum test, splitting (CPU)
  double tessellationMs = 0;   // GPU tessellation (0 on the mesh path: inside raster)
  double rasterShadingMs = 0;  // rasterisation + Blinn-Phong shading
  double crackFillingMs = 0;   // image-space crack filling (0 when off)
  double gpuTotalMs = 0;       // the frame's GPU work, submission to completion
  double renderCallMs = 0;     // Renderer::render: validation, upload, GPU, readback
  double totalMs = 0;          // the whole FrameEngine::render call
  bool gpuFromTimestamps = false;
};

struct FrameStatistics {
  int64_t pieces = 0;            // Bézier pieces in the plan
  int64_t visiblePieces = 0;     // pieces not discarded by the CPU frustum test
  int64_t splitPieces = 0;       // visible pieces with level > 64, split into 4^k
  int64_t renderPatches = 0;     // patches sent to the renderer
  int64_t plannedTriangles = 0;  // triangles of all render patches (CPU count)
  uint64_t triangles = 0;        // triangles the GPU generated (patches it did not cull)
  uint32_t gpuCulledPatches = 0;
  int maxPieceLevel = 0;        // largest FMM86 level before splitting
  int rings = 0;                // extraordinary rings
  double averageRingDepth = 0;  // FAS steps per ring below its Far level (Eq. (4) depth)
  int maxRingDepth = 0;
  double averageRingLevel = 0;  // Far isolation level + FAS steps: innermost pieces' level
  int maxRingLevel = 0;         //   below the base face
  double guaranteedBound = 0;   // object space: max over pieces of approximation + FMM86 bound
};

// The CPU half of a frame: what would be uploaded, and why.
struct PreparedFrame {
  TessellationPlan plan;             // patch ids are indices into plan.pieces
  std::vector<RenderPatch> patches;  // visible pieces, split to levels ≤ 64
  Camera camera;                     // the renderer's camera for the request
  RenderOptions options;
  FrameStatistics statistics;  // triangles and gpuCulledPatches are left at 0
  FrameTimings timings;        // planMs and patchesMs
};

struct EngineFrame {
  Frame frame;  // colour, patch ids (= plan piece indices), depth, renderer timings
  TessellationPlan plan;
  FrameStatistics statistics;
  FrameTimings timings;
};

// The tessellation options a request plans with (camera set in pixel-accurate mode only).
TessellationOptions tessellationOptionsFor(const FrameRequest& request);

// Validates the request (see the errors above), plans, culls and splits; no device needed.
PreparedFrame prepareFrame(const PatchSet& patches, const FrameRequest& request);

class FrameEngine {
 public:
  static FrameEngine create(const DeviceSelection& selection);
  explicit FrameEngine(Renderer renderer);

  EngineFrame render(const PatchSet& patches, const FrameRequest& request);
  Renderer& renderer() { return renderer_; }

 private:
  Renderer renderer_;
};

}  // namespace tessera::gpu
