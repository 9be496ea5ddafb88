#include "core/tessellate.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "core/adaptive_surface.h"
#include "core/adaptive_tessellator.h"
#include "core/error.h"
#include "core/tessellation_plan.h"

namespace tessera {

namespace {
double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The user path for a tolerance: tiles over the surface tree (docs/ADAPTIVE.md).
TessellationResult tessellateToTolerance(const PatchSet& patches, const TessellationOptions& options) {
  const AdaptiveSurface& surface = *patches.adaptive;
  auto start = std::chrono::steady_clock::now();
  const AdaptiveLayout layout = layoutAdaptive(patches, surface, options);
  const AdaptivePlan& plan = layout.plan;
  TessellationResult result;
  result.summary.planMs = millisecondsSince(start);
  start = std::chrono::steady_clock::now();
  result.mesh = tessellateAdaptive(patches, surface, layout, options.recordParameters, options.checkpoint);
  result.summary.tessellateMs = millisecondsSince(start);
  TessellationSummary& s = result.summary;
  s.triangles = int64_t(result.mesh.triangleCount());
  s.vertices = int64_t(result.mesh.positions.size());
  s.pieces = int64_t(plan.tiles.size());
  s.rings = int(patches.rings.size());
  long levels = 0;
  for (const Tile& tile : plan.tiles) {
    levels += tile.level;
    s.maxDepth = std::max(s.maxDepth, tile.level);
  }
  s.averageDepth = plan.tiles.empty() ? 0.0 : double(levels) / double(plan.tiles.size());
  s.guaranteedBound = plan.guaranteedBound + options.encodingReserve;
  s.tolerance = plan.tiles.empty() ? 0.0 : plan.tolerance + options.encodingReserve;
  return result;
}

}  // namespace

TessellationResult tessellate(const PatchSet& patches, const ControlMesh& mesh,
                              const TessellationOptions& options) {
  validateTessellationOptions(options);
  if (options.uniformLevel == 0 && options.eta > 0 && patches.adaptive) return tessellateToTolerance(patches, options);
  auto start = std::chrono::steady_clock::now();
  TessellationPlan plan = planTessellation(patches, options);
  TessellationResult result;
  result.summary.planMs = millisecondsSince(start);
  int64_t estimate = estimateTriangles(plan);
  if (estimate > options.maxTriangles) {
    throwLimit("the request would produce about " + std::to_string(estimate) +
               " triangles, over the budget of " + std::to_string(options.maxTriangles) +
               "; raise the tolerance or the triangle budget");
  }
  if (options.beforeOutput) options.beforeOutput(estimate);
  start = std::chrono::steady_clock::now();
  FaceTopology faces(mesh.faceSizes, mesh.faceVertices);
  result.mesh = tessellatePlan(plan, faces, options.recordParameters, options.checkpoint);
  result.summary.tessellateMs = millisecondsSince(start);
  TessellationSummary& s = result.summary;
  s.triangles = int64_t(result.mesh.triangleCount());
  s.vertices = int64_t(result.mesh.positions.size());
  s.pieces = int64_t(plan.pieces.size());
  s.rings = plan.rings;
  s.averageDepth = plan.averageDepth;
  s.maxDepth = plan.maxDepth;
  s.guaranteedBound = plan.guaranteedBound + options.encodingReserve;
  s.tolerance = options.uniformLevel > 0 ? plan.tolerance : plan.tolerance + options.encodingReserve;
  result.plan = std::move(plan);
  return result;
}

}  // namespace tessera
