// A long tessellation reaches its checkpoint (TessellationOptions::checkpoint, which a server
// throws from when the call is cancelled or past its deadline) often in every stage: planning,
// stitching, evaluation and triangulation, the UVs and the GLB writer. Measured as the longest
// stretch of the whole job without a call, against the job's own time (so that a busy machine,
// which slows both, does not change the verdict): a stage without checkpoints inside it is most
// of the job on the torus at 1e-6, 3 M triangles with UVs (the UVs alone were 40 % of it).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/glb_output.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
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

}  // namespace
}  // namespace tessera
