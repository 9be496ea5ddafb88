#include "core/tessellate.h"

#include <chrono>
#include <string>

#include "core/error.h"
#include "core/tessellation_plan.h"

namespace tessera {

namespace {
double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

TessellationResult tessellate(const PatchSet& patches, const ControlMesh& mesh,
                              const TessellationOptions& options) {
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
  s.guaranteedBound = plan.guaranteedBound;
  s.tolerance = plan.tolerance;
  result.plan = std::move(plan);
  return result;
}

}  // namespace tessera
