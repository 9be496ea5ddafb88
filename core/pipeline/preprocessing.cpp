#include "core/pipeline/preprocessing.h"

#include "core/surface/adaptive_surface.h"
#include "core/surface/tolerance_model.h"
#include "core/topology/refinement_input.h"

namespace tessera {

PatchSet buildPatchSet(const ControlMesh& mesh, const PreprocessingOptions& options) {
  validateControlMesh(mesh);
  const RefinementInput input(mesh);
  PatchSet patches = reduceToPatches(mesh, input, options);
  patches.adaptive = buildAdaptiveSurface(patches, input, mesh, options.checkpoint,
                                          chainFloorFor(options.finestRelativeTolerance));
  return patches;
}

double finestRelativeTolerance(const ControlMesh& mesh, const TessellationOptions& options) {
  if (options.accuracy.uniform() || mesh.positions.empty()) return 0;
  Vec3 lo, hi;
  mesh.bounds(lo, hi);
  const double diagonal = length(Vec3d(hi) - Vec3d(lo));
  if (!(diagonal > 0)) return 0;
  // The surface is relative to the mesh's origin; a camera is in model units (tessellate.h).
  TessellationOptions relative = options;
  relative.encodingReserve = 0;
  if (relative.camera) {
    relative.camera->eye = relative.camera->eye - mesh.origin;
    relative.camera->target = relative.camera->target - mesh.origin;
  }
  const float boxLo[3] = {lo.x, lo.y, lo.z}, boxHi[3] = {hi.x, hi.y, hi.z};
  return ToleranceModel(relative, lo, hi).forBox(boxLo, boxHi) / diagonal;
}

}  // namespace tessera
