// Planning into a reused plan: the pieces must be exactly those of a fresh plan, whatever the
// reused plan held before.
#include "core/pipeline/preprocessing.h"
#include "core/uniform/tessellation_plan.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "reference/models.h"

namespace tessera {
namespace {

template <typename T>
bool sameBits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

bool sameDomain(const PatchDomain& a, const PatchDomain& b) {
  return a.baseFace == b.baseFace && a.subFace == b.subFace && sameBits(a.origin, b.origin) &&
         sameBits(a.axisS, b.axisS) && sameBits(a.axisT, b.axisT);
}

bool samePiece(const BezierPiece& a, const BezierPiece& b) {
  return sameBits(a.bezier, b.bezier) && sameDomain(a.domain, b.domain) && a.kind == b.kind &&
         a.depth == b.depth && a.level == b.level && a.ring == b.ring &&
         sameBits(a.approximationBound, b.approximationBound) &&
         sameBits(a.tessellationBound, b.tessellationBound) && sameBits(a.tolerance, b.tolerance);
}

void expectSamePlan(const TessellationPlan& expected, const TessellationPlan& actual,
                    const std::string& what) {
  ASSERT_EQ(expected.pieces.size(), actual.pieces.size()) << what;
  size_t differing = 0;
  for (size_t p = 0; p < expected.pieces.size(); ++p)
    differing += !samePiece(expected.pieces[p], actual.pieces[p]);
  EXPECT_EQ(differing, 0u) << what;
  ASSERT_EQ(expected.evNormals.size(), actual.evNormals.size()) << what;
  for (size_t r = 0; r < expected.evNormals.size(); ++r) {
    EXPECT_TRUE(sameBits(expected.evNormals[r], actual.evNormals[r])) << what << ", ring " << r;
  }
  EXPECT_EQ(expected.rings, actual.rings) << what;
  EXPECT_TRUE(sameBits(expected.averageDepth, actual.averageDepth)) << what;
  EXPECT_EQ(expected.maxDepth, actual.maxDepth) << what;
  EXPECT_TRUE(sameBits(expected.guaranteedBound, actual.guaranteedBound)) << what;
  EXPECT_TRUE(sameBits(expected.tolerance, actual.tolerance)) << what;
}

PatchSet loadPatches(const std::string& name) {
  return buildPatchSet(readObjFile(testing::modelsDir() + "/" + name + ".obj"));
}

TessellationOptions uniform(int p) {
  TessellationOptions options;
  options.accuracy = Accuracy::uniformLevel(p);
  return options;
}

TessellationOptions relative(double tolerance) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(tolerance);
  return options;
}

TessellationOptions camera(const PatchSet& set) {
  TessellationOptions options;
  Camera c;
  const Vec3d lo(set.boundsMin), hi(set.boundsMax);
  c.target = (lo + hi) * 0.5;
  c.eye = c.target + Vec3d(0.3, 0.4, 2.0) * length(hi - lo);
  options.accuracy = Accuracy::pixel(0.5);
  options.camera = c;
  return options;
}

// One plan object through requests that grow, shrink and change model, mode and bound, as a
// viewer's plan would from frame to frame.
TEST(TessellationPlan, ReusedPlanEqualsAFreshOne) {
  const PatchSet bigguy = loadPatches("bigguy"), car = loadPatches("car");
  const std::vector<std::pair<const PatchSet*, TessellationOptions>> requests = {
      {&bigguy, uniform(64)}, {&bigguy, uniform(64)}, {&car, relative(1e-3)},
      {&bigguy, uniform(16)}, {&car, uniform(64)},    {&bigguy, camera(bigguy)},
      {&car, relative(1e-4)}, {&car, uniform(3)}};
  TessellationPlan reused;
  for (size_t k = 0; k < requests.size(); ++k) {
    const auto& [patches, options] = requests[k];
    planTessellation(*patches, options, reused);
    expectSamePlan(planTessellation(*patches, options), reused, "request " + std::to_string(k));
  }
}

}  // namespace
}  // namespace tessera
