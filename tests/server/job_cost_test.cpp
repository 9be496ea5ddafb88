// TessellationCosts: a content never tessellated has no estimate; otherwise an adaptive job's
// triangles scale as 1/ε and a uniform one's as level² from the largest coefficient recorded,
// per content and mode; the oldest contents are forgotten past the limit. The jobs whose estimate
// was small while they were not (job_cost.h): the single-phase path (η = 0), pixel-accurate jobs,
// quantizing encodings.
#include <gtest/gtest.h>

#include "core/pipeline/glb_output.h"
#include "server/tessellation/job_cost.h"

namespace tessera::server {
namespace {

JobShape tolerance(double relative) { return {false, 0, relative}; }
JobShape level(int p) { return {true, p, 0}; }
JobShape singlePhase(double relative) { return {false, 0, relative, true}; }
JobShape camera(double finestRelative) { return {false, 0, finestRelative, false, true}; }
JobShape quantizing(double relative) { return {false, 0, relative, false, false, true}; }

// A cube of side 2 at the origin: its diagonal is 2√3.
ControlMesh cube() {
  ControlMesh mesh;
  for (int i = 0; i < 8; ++i) mesh.positions.push_back(Vec3(i & 1 ? 1.f : -1.f, i & 2 ? 1.f : -1.f, i & 4 ? 1.f : -1.f));
  mesh.faceSizes.assign(6, 4);
  mesh.faceVertices = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  return mesh;
}

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

// η = 0 runs the single-phase path, which made bigguy 19,562 triangles at 1e-2 where the adaptive
// path made 2,900: estimated from the adaptive coefficient, it would have been taken for light.
TEST(JobCost, TheSinglePhasePathHasItsOwnCoefficients) {
  TessellationCosts costs;
  costs.record("a", tolerance(1e-2), 2'900);
  EXPECT_FALSE(costs.estimate("a", singlePhase(1e-3))) << "no single-phase job recorded yet";
  costs.record("a", singlePhase(1e-2), 19'562);
  EXPECT_NEAR(*costs.estimate("a", singlePhase(1e-3)), 195'620, 1e-6);
  EXPECT_NEAR(*costs.estimate("a", tolerance(1e-3)), 29'000, 1e-6) << "the adaptive coefficient unchanged";
}

// A pixel job with the camera close to the mesh has a fine finest tolerance and few triangles
// (most of the mesh is far): recorded as a tolerance job, its coefficient made the next tolerance
// job's estimate a fraction of what it made. It records nothing, and is estimated from the
// tolerance jobs' coefficient at its finest tolerance (more than it makes).
TEST(JobCost, APixelJobRecordsNothingAndIsEstimatedFromTheToleranceJobs) {
  TessellationCosts costs;
  costs.record("a", camera(1e-5), 20'000);
  EXPECT_FALSE(costs.estimate("a", tolerance(1e-3))) << "the pixel job's coefficient was used";
  EXPECT_FALSE(costs.estimate("a", camera(1e-5)));
  costs.record("a", tolerance(1e-2), 3'000);
  EXPECT_NEAR(*costs.estimate("a", camera(1e-5)), 3'000'000, 1e-3);
  costs.record("a", camera(1e-5), 20'000);
  EXPECT_NEAR(*costs.estimate("a", tolerance(1e-3)), 30'000, 1e-6) << "the pixel job lowered nothing";
}

// A quantized or meshopt job plans to ε less the grid's error, up to kQuantizationShare of ε:
// estimated at that smaller tolerance; it records at its ε (erring high for float jobs).
TEST(JobCost, AQuantizingJobIsEstimatedAtItsToleranceLessTheGridsShare) {
  TessellationCosts costs;
  costs.record("a", tolerance(1e-2), 7'000);
  EXPECT_NEAR(*costs.estimate("a", quantizing(1e-3)), 70'000 / (1 - kQuantizationShare), 1e-6);
  costs.record("a", quantizing(1e-2), 8'000);
  EXPECT_NEAR(*costs.estimate("a", tolerance(1e-3)), 80'000, 1e-6);
}

TEST(JobCost, TheShapeOfAJobNamesItsPathCameraAndEncoding) {
  const ControlMesh mesh = cube();
  TessellationJob job;
  job.accuracy = Accuracy::relative(1e-3);
  JobShape shape = shapeOf(mesh, job);
  EXPECT_FALSE(shape.uniform || shape.singlePhase || shape.camera || shape.quantizing);
  EXPECT_NEAR(shape.relativeTolerance, 1e-3, 1e-12);
  job.eta = 0;
  job.encoding = GlbEncoding::kMeshopt;
  shape = shapeOf(mesh, job);
  EXPECT_TRUE(shape.singlePhase && shape.quantizing);
  job.eta = 0.5;
  job.encoding = GlbEncoding::kFloat;
  job.accuracy = Accuracy::pixel(1);
  job.camera = Camera{};
  job.camera->eye = Vec3d(0, 0, 5);
  job.camera->target = Vec3d(0, 0, 0);
  job.camera->up = Vec3d(0, 1, 0);
  shape = shapeOf(mesh, job);
  EXPECT_TRUE(shape.camera);
  EXPECT_GT(shape.relativeTolerance, 0);
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
