#include "core/topology/refinement_budget.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/base/error.h"
#include "core/topology/far_topology.h"

namespace tessera {

namespace {
constexpr double kHopeless = 8;
}  // namespace

int64_t requireRefinementWithin(const ControlMesh& mesh, int64_t maxRefinedVertices,
                             const std::function<void()>& checkpoint) {
  const int isolation = isolationLevelFor(mesh);
  // Levels where semi-sharp features still refine (past them only extraordinary vertices are
  // isolated, a region that does not grow).
  const int creaseLevels = int(std::ceil(maxSemiSharpness(mesh)));
  const Far::PatchTableFactory::Options options = patchTableOptions(isolation);
  double estimate = 0;
  int probed = 0;
  bool exact = false;
  for (int probe = 1; probe <= isolation; ++probe) {
    if (checkpoint) checkpoint();
    std::unique_ptr<Far::TopologyRefiner> refiner = createTopologyRefiner(mesh);
    Far::PatchTableFactory::Options partial = options;
    partial.maxIsolationLevel = probe;
    refineAdaptively(*refiner, partial);
    const int reached = refiner->GetMaxLevel();
    probed = reached;
    estimate = refiner->GetNumVerticesTotal();
    // Far stopped early (nothing is left to refine) or went all the way: the count is exact.
    exact = reached < probe || reached == isolation;
    if (exact) break;
    const double last = refiner->GetLevel(reached).GetNumVertices();
    const double growth = std::max(1.0, last / refiner->GetLevel(reached - 1).GetNumVertices());
    const auto factor = [&](int level) { return level <= creaseLevels ? growth : 1.0; };
    double next = last;
    for (int level = reached + 1; level <= isolation; ++level) estimate += next *= factor(level);
    const double limit = double(maxRefinedVertices);
    if (estimate <= limit) return int64_t(std::ceil(estimate));
    // The extrapolation overestimates, by 2-3 times where growth falls fast; past 8 times no
    // deeper look will bring it within. Nor is one taken that would itself pass twice the limit.
    if (estimate > kHopeless * limit || double(refiner->GetNumVerticesTotal()) + last * factor(reached + 1) > 2 * limit) {
      break;
    }
  }
  if (estimate <= double(maxRefinedVertices)) return int64_t(std::ceil(estimate));
  const std::string how =
      exact ? "" : " (extrapolated from " + std::to_string(probed) + " of its " + std::to_string(isolation) + " levels)";
  throwLimit("OpenSubdiv's adaptive refinement of the mesh (semi-sharp creases are isolated level by level) "
             "would make about " + std::to_string(int64_t(estimate)) + " vertices" + how + ", over the limit of " +
             std::to_string(maxRefinedVertices) + " (max_refined_vertices); lower the sharpness or raise the limit");
}

}  // namespace tessera
