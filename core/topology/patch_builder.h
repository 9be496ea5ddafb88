// Preprocessing's reduction (paper §3.2, docs/DECISIONS.md "Preprocessing"): a control mesh,
// through OpenSubdiv Far, to its regular B-spline patches and extraordinary rings in CER
// (core/rings/patch_set.h). core/pipeline/preprocessing.h adds the adaptive surface over them.
#pragma once

#include <cstdint>
#include <functional>

#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"
#include "core/topology/refinement_input.h"

namespace tessera {

// What building a patch set may cost. `checkpoint`, when given, is called between stages and for
// every ring and root (well under a second apart on any mesh the limits admit) and may throw to
// abandon the work: how a server stops preprocessing for a call that was cancelled.
// `maxRefinedVertices` (0: no limit) bounds OpenSubdiv's adaptive refinement, the part that grows
// with semi-sharp creases (core/topology/refinement_budget.h): a mesh over it is refused before the memory
// is taken. `beforeRefining`, when given, gets that estimate of the refined vertices before the
// refinement is made, and `afterRefining` the exact count once it is, before the patches are
// built (either may throw): how a server reserves memory for the job as it learns its size
// (core/pipeline/memory_estimates.h).
// `finestRelativeTolerance`: the finest tolerance (a fraction of the bounding-box diagonal) the
// adaptive surface must serve, which sets how deep its EV chains go (core/surface/surface_tree.h,
// chainFloorFor); 0 serves any (core/pipeline/preprocessing.h, finestRelativeTolerance, says what a
// request needs).
struct PreprocessingOptions {
  std::function<void()> checkpoint;
  int64_t maxRefinedVertices = 0;
  std::function<void(int64_t refinedVertices)> beforeRefining = {};
  std::function<void(int64_t refinedVertices)> afterRefining = {};
  double finestRelativeTolerance = 0;
};

// Reduces a validated control mesh (`input`: what Far refines for it) to regular patches and
// rings, with its UVs on the limit surface when it has any; `adaptive` is left empty. Throws
// TesseraError for unsupported input (features that cannot be reduced to the canonical pieces)
// and for a refinement over the options' limit.
PatchSet reduceToPatches(const ControlMesh& mesh, const RefinementInput& input, const PreprocessingOptions& options);

}  // namespace tessera
