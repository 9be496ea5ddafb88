// The AVX2 grid kernel against the scalar reference, bit for bit, on the pieces of real models.
// The kernel has three shapes of work, and every one must be exercised: N + 1 < 8 (samples
// gathered across rows by lane permutations; N = 1 stores only 4 of 8 lanes), N + 1 a multiple of
// 8 (whole vectors), and N + 1 ≥ 8 with a tail (the last vector overlaps the one before it).
#include "core/grid_evaluation.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/obj_reader.h"
#include "tests/support/models.h"

namespace tessera {
namespace {

struct LevelClasses {
  size_t small = 0, single = 0, whole = 0, tail = 0;  // N + 1 < 8, N = 1, multiple of 8, tail

  void count(const std::vector<BezierPiece>& pieces) {
    for (const BezierPiece& piece : pieces) {
      const int side = piece.level + 1;
      small += side < 8;
      single += side == 2;
      whole += side >= 8 && side % 8 == 0;
      tail += side >= 8 && side % 8 != 0;
    }
  }
};

// The first sample whose bits differ, or -1.
long firstDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(&a[i], &b[i], sizeof(Vec3)) != 0) return long(i);
  }
  return -1;
}

TEST(GridEvaluation, VectorKernelEqualsScalarBitForBitOnEveryLevelClass) {
  LevelClasses classes;
  for (const char* name : {"bigguy", "car"}) {
    const PatchSet set = buildPatchSet(readObjFile(testing::modelsDir() + "/" + name + ".obj"));
    std::vector<TessellationOptions> requests(3);
    requests[0].uniformLevel = 64;         // sides 65, 33, 17, 9 (tails), 5, 3, 2
    requests[1].uniformLevel = 15;         // sides 16, 8 (whole vectors), 4, 2
    requests[2].relativeTolerance = true;  // whatever levels FMM86 picks
    requests[2].tolerance = 1e-4;
    for (const TessellationOptions& options : requests) {
      const TessellationPlan plan = planTessellation(set, options);
      std::vector<size_t> offsets;
      gridOffsets(plan.pieces, offsets);
      // Filled with different garbage, so that a sample neither kernel wrote cannot pass.
      std::vector<Vec3> vector(offsets.back(), Vec3(1, 2, 3)),
          scalar(offsets.back(), Vec3(4, 5, 6));
      evaluatePieceGrids(plan.pieces, offsets, vector.data(), GridKernel::kAvx2);
      evaluatePieceGrids(plan.pieces, offsets, scalar.data(), GridKernel::kScalar);
      EXPECT_EQ(firstDifference(vector, scalar), -1)
          << name << ", uniform level " << options.uniformLevel << ", " << vector.size()
          << " samples";
      classes.count(plan.pieces);
    }
  }
  EXPECT_GT(classes.small, 0u);
  EXPECT_GT(classes.single, 0u);
  EXPECT_GT(classes.whole, 0u);
  EXPECT_GT(classes.tail, 0u);
}

}  // namespace
}  // namespace tessera
