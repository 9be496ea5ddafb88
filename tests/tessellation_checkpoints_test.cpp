// A long tessellation reaches its checkpoint (TessellationOptions::checkpoint, which a server
// throws from when the call is cancelled or past its deadline) often in every stage: planning,
// stitching, evaluation and triangulation, the UVs and the GLB writer. Measured as the longest
// stretch of the whole job without a call, against the job's own time (so that a busy machine,
// which slows both, does not change the verdict): a stage without checkpoints inside it is most
// of the job on the torus at 1e-6, 3 M triangles with UVs (the UVs alone were 40 % of it).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <functional>
#include <mutex>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/output/glb_writer.h"
#include "core/pipeline/glb_output.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
#include "core/stitching/adaptive_tessellator.h"
#include "reference/models.h"

namespace tessera {
namespace {

using Clock = std::chrono::steady_clock;

// When each checkpoint came (from any thread), and the longest stretch without one.
class CheckpointClock {
 public:
  void mark() {
    std::lock_guard lock(mutex_);
    marks_.push_back(Clock::now());
  }
  // The longest stretch from the start, between marks, and to now; and the whole time.
  std::pair<double, double> longestGapAndTotal() {
    const Clock::time_point end = Clock::now();
    std::vector<Clock::time_point> at = marks_;
    std::sort(at.begin(), at.end());
    at.push_back(end);
    double longest = 0;
    Clock::time_point last = start_;
    for (const Clock::time_point t : at) longest = std::max(longest, seconds(t - last)), last = t;
    return {longest, seconds(end - start_)};
  }
  size_t count() const { return marks_.size(); }

 private:
  static double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }
  std::mutex mutex_;
  std::vector<Clock::time_point> marks_;
  const Clock::time_point start_ = Clock::now();
};

TEST(TessellationCheckpoints, NoStageOfALargeRequestRunsLongWithoutOne) {
  const ControlMesh mesh = readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_torus.obj");
  ASSERT_TRUE(mesh.hasUvs());
  TessellationOptions options;
  options.accuracy = Accuracy::relative(1e-6);
  PreprocessingOptions preprocessing;
  preprocessing.finestRelativeTolerance = finestRelativeTolerance(mesh, options);
  const PatchSet patches = buildPatchSet(mesh, preprocessing);
  for (GlbEncoding encoding : {GlbEncoding::kFloat}) {
    SCOPED_TRACE(glbEncodingName(encoding));
    CheckpointClock clock;
    TessellationOptions job = options;
    job.checkpoint = [&clock] { clock.mark(); };
    const std::optional<PositionQuantization> positions = reserveForEncoding(encoding, patches, job);
    const TessellationResult result = tessellate(patches, mesh, job);
    const std::vector<uint8_t> glb = writeGlb(result.mesh, glbOptionsFor({encoding, "torus", ""}, job, result.summary, positions));
    const auto [gap, total] = clock.longestGapAndTotal();
    EXPECT_GT(result.summary.triangles, 2'000'000);
    EXPECT_LE(gap, 0.25 * total) << "longest stretch without a checkpoint " << gap << " s of " << total << " s ("
                                 << clock.count() << " checkpoints)";
  }
}

// Stitching, evaluation and triangulation reach the checkpoint by work done, not once per part of
// up to 16 roots: on the cube (six roots, a part each) at 1e-6, each root is ~140K vertices.
// Counted, not timed (a busy machine changes nothing): at least a call for every 32768 vertices
// the output has, in stitching and again in evaluation and triangulation (the code's intervals
// are 16384 points or less); the part-wise checks alone made 7 and 13 calls here.
TEST(TessellationCheckpoints, StitchingAndEvaluationReachOneByWorkNotByRoots) {
  const ControlMesh mesh = readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_cube.obj");
  TessellationOptions options;
  options.accuracy = Accuracy::relative(1e-6);
  PreprocessingOptions preprocessing;
  preprocessing.finestRelativeTolerance = finestRelativeTolerance(mesh, options);
  const PatchSet patches = buildPatchSet(mesh, preprocessing);
  const AdaptiveSurface& surface = *patches.adaptive;
  const AdaptiveLayout layout = layoutAdaptive(patches, surface, options);
  const size_t vertices = layout.stitching.vertices.size();
  ASSERT_LE(surface.tree.roots.size(), 6u);
  ASSERT_GE(vertices, 500'000u) << "too few vertices for the check";
  std::atomic<size_t> calls{0};
  const std::function<void()> count = [&calls] { calls.fetch_add(1, std::memory_order_relaxed); };
  const Stitching stitching = stitchTiles(layout.plan, surface.tree, surface.lines, count);
  EXPECT_EQ(stitching.vertices.size(), vertices) << "stitched again, the same vertices";
  EXPECT_GE(calls.load(), vertices / 32768) << "stitching " << layout.plan.tiles.size() << " tiles, " << vertices
                                            << " vertices";
  const size_t stitchingCalls = calls.exchange(0);
  const TriangleMesh triangles = tessellateAdaptive(patches, surface, layout, false, count);
  EXPECT_GE(calls.load(), vertices / 32768) << "evaluating and triangulating " << vertices << " vertices";
  std::printf("%zu tiles, %zu vertices: %zu checkpoints stitching, %zu evaluating and triangulating\n",
              layout.plan.tiles.size(), vertices, stitchingCalls, calls.load());
}

// meshoptimizer's orderings and codecs on a large mesh (the torus at 1e-6 with UVs, 3 M
// triangles): no stretch of the meshopt encoding without a checkpoint is more than a quarter of
// its time. The vertex-cache ordering in one piece was ~60 % of it; in runs of 512K triangles
// each is a sixth of the ordering. Prints the longest stretch (bench/RUNAWAY-RESULTS.md).
TEST(TessellationCheckpoints, TheMeshoptEncodingOfALargeMeshHasNoLongStretchWithoutOne) {
  const ControlMesh mesh = readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_torus.obj");
  TessellationOptions options;
  options.accuracy = Accuracy::relative(1e-6);
  PreprocessingOptions preprocessing;
  preprocessing.finestRelativeTolerance = finestRelativeTolerance(mesh, options);
  const PatchSet patches = buildPatchSet(mesh, preprocessing);
  const std::optional<PositionQuantization> positions = reserveForEncoding(GlbEncoding::kMeshopt, patches, options);
  const TessellationResult result = tessellate(patches, mesh, options);
  ASSERT_GT(result.summary.triangles, 2'000'000);
  CheckpointClock clock;
  GlbOptions glb = glbOptionsFor({GlbEncoding::kMeshopt, "torus", ""}, options, result.summary, positions);
  glb.checkpoint = [&clock] { clock.mark(); };
  const std::vector<uint8_t> bytes = writeGlb(result.mesh, glb);
  const auto [gap, total] = clock.longestGapAndTotal();
  std::printf("meshopt encoding of %lld triangles: %.3f s, longest stretch without a checkpoint %.3f s "
              "(%zu checkpoints)\n",
              static_cast<long long>(result.summary.triangles), total, gap, clock.count());
  EXPECT_FALSE(bytes.empty());
  EXPECT_LE(gap, 0.25 * total) << "longest stretch without a checkpoint " << gap << " s of " << total << " s ("
                               << clock.count() << " checkpoints)";
}

}  // namespace
}  // namespace tessera
