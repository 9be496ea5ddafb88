#include "reference/far_reference.h"

#include <limits>

namespace tessera::testing {

namespace {
void fillOffsets(FarRefinement& far, const ControlMesh& mesh) {
  far.positions = refinedPositions(*far.refiner, mesh.positions);
  far.levelOffsets.assign(1, 0);
  for (int l = 0; l < far.refiner->GetMaxLevel(); ++l) {
    far.levelOffsets.push_back(far.levelOffsets.back() + far.refiner->GetLevel(l).GetNumVertices());
  }
}
}  // namespace

FarRefinement FarRefinement::uniform(const ControlMesh& mesh, int levels) {
  FarRefinement far;
  far.refiner = createTopologyRefiner(mesh);
  Far::TopologyRefiner::UniformOptions options(levels);
  options.fullTopologyInLastLevel = true;
  far.refiner->RefineUniform(options);
  fillOffsets(far, mesh);
  return far;
}

FarRefinement FarRefinement::adaptive(const ControlMesh& mesh, int isolationLevel) {
  FarRefinement far;
  far.refiner = createTopologyRefiner(mesh);
  Far::TopologyRefiner::AdaptiveOptions options(isolationLevel);
  options.useInfSharpPatch = true;
  far.refiner->RefineAdaptive(options);
  fillOffsets(far, mesh);
  return far;
}

FarRingLevel farRingLevel(const FarRefinement& far, int level, Index parentEv, Index parentSpoke) {
  const auto& parent = far.refiner->GetLevel(level - 1);
  FarRingLevel result;
  result.ev = parent.GetVertexChildVertex(parentEv);
  result.firstSpoke = parent.GetEdgeChildVertex(parent.FindEdge(parentEv, parentSpoke));
  LatticeWalker walker(far.refiner->GetLevel(level));
  auto sectors = walker.sectorsAround(result.ev, result.firstSpoke);
  if (!sectors) return result;
  for (Index v : walker.gather(*sectors, 3)) {
    double nan = std::numeric_limits<double>::quiet_NaN();
    result.refinedPoints.push_back(v >= 0 ? far.position(level, v) : Vec3d(nan, nan, nan));
  }
  return result;
}

}  // namespace tessera::testing
