// What preprocessing a control mesh may cost, and what it must serve (core/topology/patch_topology.h,
// core/topology/patch_builder.h, core/pipeline/preprocessing.h).
#pragma once

#include <cstdint>
#include <functional>

namespace tessera {

// What preprocessing may cost. `checkpoint`, when given, is called between stages and for
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

}  // namespace tessera
