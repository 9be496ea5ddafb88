#include "reference/far_distance.h"

#include <algorithm>
#include <vector>

#include "reference/far_reference.h"
#include "reference/triangle_bvh.h"

namespace tessera::testing {

double distanceToFarRefinement(const ControlMesh& cage, int level, const TriangleMeshView& mesh) {
  const FarRefinement far = FarRefinement::uniform(cage, level);
  const auto& last = far.refiner->GetLevel(level);
  std::vector<Vec3> positions(size_t(last.GetNumVertices()));
  for (int v = 0; v < last.GetNumVertices(); ++v) positions[size_t(v)] = Vec3(far.position(level, v));
  std::vector<uint32_t> indices;
  for (int f = 0; f < last.GetNumFaces(); ++f) {
    const auto corners = last.GetFaceVertices(f);
    for (int k = 1; k + 1 < corners.size(); ++k) {
      for (int c : {0, k, k + 1}) indices.push_back(uint32_t(corners[c]));
    }
  }
  const TriangleBvh refined(positions, indices);
  double worst = 0;
  for (const Vec3& p : mesh.positions) worst = std::max(worst, refined.nearest(Vec3d(p)).distance);
  constexpr double kWeights[7][3] = {{1 / 3., 1 / 3., 1 / 3.}, {.5, .5, 0}, {0, .5, .5}, {.5, 0, .5},
                                     {2 / 3., 1 / 6., 1 / 6.}, {1 / 6., 2 / 3., 1 / 6.}, {1 / 6., 1 / 6., 2 / 3.}};
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const Vec3d a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]),
        c(mesh.positions[mesh.indices[t + 2]]);
    for (const auto& w : kWeights) worst = std::max(worst, refined.nearest(a * w[0] + b * w[1] + c * w[2]).distance);
  }
  return worst;
}

}  // namespace tessera::testing
