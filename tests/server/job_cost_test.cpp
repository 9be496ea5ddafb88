// TessellationCosts: a content never tessellated has no estimate; otherwise an adaptive job's
// triangles scale as 1/ε and a uniform one's as 4^level from the largest coefficient recorded,
// per content and mode; the oldest contents are forgotten past the limit.
#include <gtest/gtest.h>

#include "server/tessellation/job_cost.h"

namespace tessera::server {
namespace {

JobShape tolerance(double relative) { return {false, 0, relative}; }
JobShape level(int p) { return {true, p, 0}; }

TEST(JobCost, AContentNeverTessellatedHasNoEstimate) {
  TessellationCosts costs;
  EXPECT_FALSE(costs.estimate("a", tolerance(1e-2)));
  costs.record("a", tolerance(1e-2), 20'000);
  EXPECT_FALSE(costs.estimate("b", tolerance(1e-2))) << "another content";
  EXPECT_FALSE(costs.estimate("a", level(3))) << "another mode";
}

TEST(JobCost, TrianglesScaleAsOneOverTheToleranceAndTheLevelSquared) {
  TessellationCosts costs;
  costs.record("a", tolerance(1e-2), 20'000);
  EXPECT_NEAR(*costs.estimate("a", tolerance(1e-2)), 20'000, 1e-6);
  EXPECT_NEAR(*costs.estimate("a", tolerance(1e-4)), 2'000'000, 1e-3);
  costs.record("a", level(2), 1'600);
  EXPECT_NEAR(*costs.estimate("a", level(8)), 1'600 * 16, 1e-6);
}

TEST(JobCost, TheLargestCoefficientSeenIsKept) {
  TessellationCosts costs;
  costs.record("a", tolerance(1e-2), 30'000);  // a coarse job's floor inflates its coefficient
  costs.record("a", tolerance(1e-3), 200'000);
  EXPECT_NEAR(*costs.estimate("a", tolerance(1e-3)), 300'000, 1e-6);
}

TEST(JobCost, TheOldestContentsAreForgottenPastTheLimit) {
  TessellationCosts costs(2);
  costs.record("a", tolerance(1e-2), 1);
  costs.record("b", tolerance(1e-2), 1);
  costs.record("c", tolerance(1e-2), 1);
  EXPECT_FALSE(costs.estimate("a", tolerance(1e-2)));
  EXPECT_TRUE(costs.estimate("c", tolerance(1e-2)));
}

}  // namespace
}  // namespace tessera::server
