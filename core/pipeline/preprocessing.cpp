#include "core/pipeline/preprocessing.h"

#include "core/surface/adaptive_surface.h"
#include "core/topology/refinement_input.h"

namespace tessera {

PatchSet buildPatchSet(const ControlMesh& mesh, const PreprocessingOptions& options) {
  validateControlMesh(mesh);
  const RefinementInput input(mesh);
  PatchSet patches = reduceToPatches(mesh, input, options);
  patches.adaptive = buildAdaptiveSurface(patches, input, mesh, options.checkpoint);
  return patches;
}

}  // namespace tessera
