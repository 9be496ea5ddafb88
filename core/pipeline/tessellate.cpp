#include "core/pipeline/tessellate.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "core/base/error.h"
#include "core/output/uv_seams.h"
#include "core/stitching/adaptive_tessellator.h"
#include "core/surface/adaptive_surface.h"
#include "core/surface/tolerance_model.h"
#include "core/uniform/tessellation_plan.h"

namespace tessera {

namespace {
double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// A tree whose chains stop short of what the request needs would leave tiles around EVs that
// cannot meet ε: a caller that preprocessed for a coarser tolerance (PreprocessingOptions) is a bug.
void requireDepthFor(const PatchSet& patches, const TessellationOptions& options) {
  const double diagonal = length(Vec3d(patches.boundsMax) - Vec3d(patches.boundsMin));
  if (!(diagonal > 0)) return;
  const float lo[3] = {patches.boundsMin.x, patches.boundsMin.y, patches.boundsMin.z};
  const float hi[3] = {patches.boundsMax.x, patches.boundsMax.y, patches.boundsMax.z};
  const double finest = ToleranceModel(options, patches).forBox(lo, hi) / diagonal;
  const SurfaceTree& tree = patches.adaptive->tree;
  if (tree.serves(finest)) return;
  throw std::logic_error("the patch set's EV chains stop at " + std::to_string(tree.chainFloor) +
                         " of the diagonal, too coarse for a tolerance of " + std::to_string(finest) +
                         " of it: preprocess for the request (PreprocessingOptions::finestRelativeTolerance)");
}

// The user path for a tolerance: tiles over the surface tree (docs/ADAPTIVE.md).
TessellationResult tessellateToTolerance(const PatchSet& patches, const TessellationOptions& options) {
  const AdaptiveSurface& surface = *patches.adaptive;
  requireDepthFor(patches, options);
  auto start = std::chrono::steady_clock::now();
  const AdaptiveLayout layout = layoutAdaptive(patches, surface, options);
  const AdaptivePlan& plan = layout.plan;
  TessellationResult result;
  result.summary.planMs = millisecondsSince(start);
  start = std::chrono::steady_clock::now();
  result.mesh = tessellateAdaptive(patches, surface, layout, options.recordParameters, options.checkpoint,
                                   options.vertexEvaluation);
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

TessellationResult tessellateSurface(const PatchSet& patches, const ControlMesh& mesh, const TessellationOptions& options);

// Where each triangle corner lies in its base face: recorded so by the adaptive path; the uniform
// path records (s, t) in each corner's piece, mapped here through the piece's domain. The
// checkpoint every 64K corners (50M corners at 17M triangles: most of a second).
std::vector<UvQuery> cornerParameters(const TessellationResult& result, const std::function<void()>& checkpoint) {
  const TriangleMesh& mesh = result.mesh;
  // Reserved, not zero-filled: its pages (1.6 GB at 17M triangles) are touched as the loop
  // reaches them, between checkpoints, not in one stretch before it.
  std::vector<UvQuery> corners;
  corners.reserve(mesh.indices.size());
  for (size_t c = 0; c < mesh.indices.size(); ++c) {
    if (checkpoint && (c & 0xffff) == 0xffff) checkpoint();
    const double s = mesh.triangleST[2 * c], t = mesh.triangleST[2 * c + 1];
    UvQuery& corner = corners.emplace_back();
    if (result.plan.pieces.empty()) {
      corner = {mesh.triangleFace[c / 3], mesh.triangleSubFace[c / 3], s, t};
      continue;
    }
    const PatchDomain& domain = result.plan.pieces[mesh.trianglePiece[c / 3]].domain;
    corner.face = domain.baseFace, corner.subFace = domain.subFace;
    domain.map(s, t, corner.u, corner.v);
  }
  return corners;
}

// The parameters UVs needed, dropped again when the caller did not ask for them.
void forgetParameters(TriangleMesh& mesh) {
  for (auto* values : {&mesh.triangleFace, &mesh.triangleSubFace, &mesh.vertexFace, &mesh.vertexSubFace}) std::vector<int>().swap(*values);
  for (auto* values : {&mesh.triangleST, &mesh.vertexUv}) std::vector<double>().swap(*values);
  for (auto* values : {&mesh.trianglePiece, &mesh.vertexPoint}) std::vector<uint32_t>().swap(*values);
}

}  // namespace

// A camera is in model units; the surface is relative to the mesh's origin, and so is the output.
// A mesh with UVs is tessellated with its triangles' parameters recorded, where its UVs are
// evaluated (core/output/uv_seams.h).
TessellationResult tessellate(const PatchSet& patches, const ControlMesh& mesh,
                              const TessellationOptions& options) {
  TessellationOptions relative = options;
  if (relative.camera) {
    relative.camera->eye = relative.camera->eye - mesh.origin;
    relative.camera->target = relative.camera->target - mesh.origin;
  }
  relative.recordParameters = options.recordParameters || patches.uvs;
  TessellationResult result = tessellateSurface(patches, mesh, relative);
  result.mesh.origin = mesh.origin;
  if (!patches.uvs) return result;
  if (options.checkpoint) options.checkpoint();
  attachUvs(mesh, *patches.uvs, cornerParameters(result, options.checkpoint), result.mesh, options.checkpoint);
  if (options.checkpoint) options.checkpoint();
  if (!options.recordParameters) forgetParameters(result.mesh);
  result.summary.vertices = int64_t(result.mesh.positions.size());
  return result;
}

namespace {

TessellationResult tessellateSurface(const PatchSet& patches, const ControlMesh& mesh, const TessellationOptions& options) {
  if (!options.accuracy.uniform() && options.eta > 0 && patches.adaptive) return tessellateToTolerance(patches, options);
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
  s.tolerance = options.accuracy.uniform() ? 0.0 : plan.tolerance + options.encodingReserve;  // a level asks for none
  result.plan = std::move(plan);
  return result;
}

}  // namespace

}  // namespace tessera
