#include "gpu/render_engine/frame_engine.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "core/base/error.h"
#include "gpu/render_engine/camera_conversion.h"
#include "gpu/render_engine/render_patches.h"
#include "gpu/vulkan/camera_math.h"
#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The checks that do not need the plan, in the order a user would fix them, before any
// planning work is spent: the renderer's target size, then the camera (core's rules).
Camera validatedCamera(const FrameRequest& request) {
  if (request.render.uniformLevel != 0) {
    throwInvalid(
        "render.uniformLevel must be 0: the frame engine sets every patch's levels "
        "(ask for Accuracy::uniformLevel instead)");
  }
  if (request.maxTriangles <= 0) throwInvalid("the triangle budget must be positive");
  for (auto [side, part] : {std::pair{request.camera.width, "width"}, std::pair{request.camera.height, "height"}}) {
    if (side < 1 || side > int(kMaxTargetSize)) {
      throwInvalid("camera." + std::string(part) + ": must be in [1, " + std::to_string(kMaxTargetSize) +
                   "] pixels, the renderer's largest target (got " + std::to_string(side) + ")");
    }
  }
  validateCamera(request.camera, "camera");
  return toGpuCamera(request.camera);
}

// Per ring, the level of its innermost pieces below the base face (Far isolation + FAS).
void ringLevels(const TessellationPlan& plan, FrameStatistics& stats) {
  std::vector<int> level(size_t(plan.rings), -1);
  for (const BezierPiece& piece : plan.pieces) {
    if (piece.kind == PieceKind::kInnermost && piece.ring >= 0)
      level[size_t(piece.ring)] = piece.depth;
  }
  int64_t sum = 0, counted = 0;
  for (int l : level) {
    if (l < 0) continue;
    sum += l;
    ++counted;
    stats.maxRingLevel = std::max(stats.maxRingLevel, l);
  }
  stats.averageRingLevel = counted ? double(sum) / double(counted) : 0.0;
}

}  // namespace

TessellationOptions tessellationOptionsFor(const FrameRequest& request) {
  TessellationOptions options;
  options.eta = request.eta;
  options.maxTriangles = request.maxTriangles;
  options.accuracy = request.accuracy;
  if (request.accuracy.pixelAccurate()) options.camera = request.camera;
  options.checkpoint = request.render.checkpoint;  // planning's rings and pieces
  return options;
}

namespace {

// Pieces between two checkpoints while culling and splitting: well under a millisecond of work.
constexpr size_t kPiecesPerCheckpoint = 4096;

void checkpoint(const FrameRequest& request) {
  if (request.render.checkpoint) request.render.checkpoint();
}

}  // namespace

PreparedFrame prepareFrame(const PatchSet& patches, const FrameRequest& request) {
  PreparedFrame prepared;
  prepared.camera = validatedCamera(request);
  TessellationOptions options = tessellationOptionsFor(request);

  Clock::time_point planStart = Clock::now();
  prepared.plan = planTessellation(patches, options);  // validates the rest of the options
  prepared.timings.planMs = millisecondsSince(planStart);

  Clock::time_point patchesStart = Clock::now();
  const TessellationPlan& plan = prepared.plan;
  FrameStatistics& stats = prepared.statistics;
  stats.pieces = int64_t(plan.pieces.size());
  stats.rings = plan.rings;
  stats.averageRingDepth = plan.averageDepth;
  stats.maxRingDepth = plan.maxDepth;
  stats.guaranteedBound = plan.guaranteedBound;
  ringLevels(plan, stats);

  // Cull first, count, check the budget, and only then split: a tiny tolerance must end in an
  // error, not in billions of sub-pieces.
  ViewFrustum frustum(request.camera);
  std::vector<uint32_t> visible;
  visible.reserve(plan.pieces.size());
  for (size_t i = 0; i < plan.pieces.size(); ++i) {
    if (i % kPiecesPerCheckpoint == 0) checkpoint(request);
    const BezierPiece& piece = plan.pieces[i];
    stats.maxPieceLevel = std::max(stats.maxPieceLevel, piece.level);
    if (!frustum.mayShow(piece.bezier.data(), 16)) continue;
    visible.push_back(uint32_t(i));
    stats.plannedTriangles += renderedTriangles(piece.level);
    if (stats.plannedTriangles > request.maxTriangles) {
      throwLimit("the frame would draw more than " + std::to_string(request.maxTriangles) +
                 " triangles (the request's budget); raise the tolerance or the budget");
    }
  }
  stats.visiblePieces = int64_t(visible.size());
  if (request.beforeDrawing) request.beforeDrawing(stats.plannedTriangles);
  for (size_t k = 0; k < visible.size(); ++k) {
    if (k % kPiecesPerCheckpoint == 0) checkpoint(request);
    const uint32_t i = visible[k];
    const BezierPiece& piece = plan.pieces[i];
    if (splitCount(piece.level) > 0) ++stats.splitPieces;
    appendRenderPatches(piece, i, prepared.patches);
  }
  stats.renderPatches = int64_t(prepared.patches.size());
  prepared.options = request.render;
  prepared.timings.patchesMs = millisecondsSince(patchesStart);
  return prepared;
}

FrameEngine FrameEngine::create(const DeviceSelection& selection) {
  return FrameEngine(Renderer::create(selection));
}

FrameEngine::FrameEngine(Renderer renderer) : renderer_(std::move(renderer)) {}

EngineFrame FrameEngine::render(const PatchSet& patches, const FrameRequest& request) {
  Clock::time_point start = Clock::now();
  PreparedFrame prepared = prepareFrame(patches, request);

  Clock::time_point renderStart = Clock::now();
  EngineFrame out;
  out.frame = renderer_.render(prepared.patches, prepared.camera, prepared.options);
  out.timings = prepared.timings;
  out.timings.renderCallMs = millisecondsSince(renderStart);
  const StageTimings& gpu = out.frame.timings;
  out.timings.tessellationMs = gpu.tessellationMs;
  out.timings.rasterShadingMs = gpu.rasterShadingMs;
  out.timings.crackFillingMs = gpu.crackFillingMs;
  out.timings.gpuTotalMs = gpu.gpuTotalMs;
  out.timings.gpuFromTimestamps = gpu.fromTimestamps;

  out.statistics = prepared.statistics;
  out.statistics.triangles = out.frame.trianglesGenerated;
  out.statistics.gpuCulledPatches = out.frame.patchesCulled;
  out.plan = std::move(prepared.plan);
  out.timings.totalMs = millisecondsSince(start);
  return out;
}

}  // namespace tessera::gpu
