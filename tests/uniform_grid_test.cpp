// The uniform grid (Table 2's workload) against two other code paths: its AVX2 kernel against the
// scalar reference bit for bit, and its samples against planTessellation's uniform pieces (same
// pieces, same order, converted to Bézier by the planner) evaluated in double. The kernel has
// three shapes of work, and every one must be exercised: N + 1 < 8 (samples
// gathered across rows by lane permutations; N = 1 stores only 4 of 8 lanes), N + 1 a multiple of
// 8 (whole vectors), and N + 1 ≥ 8 with a tail (the last vector overlaps the one before it).
#include "core/pipeline/preprocessing.h"
#include "core/uniform/uniform_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/math/bicubic.h"
#include "core/mesh/obj_reader.h"
#include "core/uniform/tessellation_plan.h"
#include "reference/models.h"

namespace tessera {
namespace {

PatchSet loadPatches(const std::string& name) {
  return buildPatchSet(readObjFile(testing::modelsDir() + "/" + name + ".obj"));
}

struct LevelClasses {
  size_t small[2] = {}, single[2] = {}, whole[2] = {}, tail[2] = {};  // per NetBasis

  void count(const std::vector<GridPiece>& pieces) {
    for (const GridPiece& piece : pieces) {
      const int side = piece.level + 1, basis = int(piece.basis);
      small[basis] += side < 8;
      single[basis] += side == 2;
      whole[basis] += side >= 8 && side % 8 == 0;
      tail[basis] += side >= 8 && side % 8 != 0;
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

TEST(UniformGrid, VectorKernelEqualsScalarBitForBitOnEveryLevelClass) {
  LevelClasses classes;
  for (const char* name : {"bigguy", "car"}) {
    const PatchSet set = loadPatches(name);
    // p = 64: sides 65, 33, 17, 9 (tails), 5, 3, 2; p = 15: sides 16, 8 (whole vectors), 4, 2.
    for (int p : {64, 15}) {
      UniformGrid grid;
      planUniformGrid(set, p, grid);
      // Filled with different garbage, so that a sample neither kernel wrote cannot pass.
      std::vector<Vec3> vector(grid.samples(), Vec3(1, 2, 3)), scalar(grid.samples(), Vec3(4, 5, 6));
      evaluateUniformGrid(set, grid, vector.data(), GridKernel::kAvx2);
      evaluateUniformGrid(set, grid, scalar.data(), GridKernel::kScalar);
      EXPECT_EQ(firstDifference(vector, scalar), -1)
          << name << ", uniform level " << p << ", " << vector.size() << " samples";
      classes.count(grid.pieces);
    }
  }
  for (int basis : {0, 1}) {
    EXPECT_GT(classes.small[basis], 0u) << "basis " << basis;
    EXPECT_GT(classes.single[basis], 0u) << "basis " << basis;
  }
  // Innermost (Bézier) pieces lie at depth ⌈log₂ p⌉ and are always N = 1; the weights are the
  // only difference between the bases, so the larger shapes are exercised through B-splines.
  const int bspline = int(NetBasis::kBSpline);
  EXPECT_GT(classes.whole[bspline], 0u);
  EXPECT_GT(classes.tail[bspline], 0u);
}

// The largest distance between the grid's samples and the plan's Bézier pieces evaluated in
// double at the same parameters, relative to the diagonal.
double deviationFromPlan(const PatchSet& set, const UniformGrid& grid, const TessellationPlan& plan,
                         const std::vector<Vec3>& samples) {
  double worst = 0;
  for (size_t q = 0; q < plan.pieces.size(); ++q) {
    const BezierPiece& piece = plan.pieces[q];
    const int n = piece.level;
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        Vec3d exact = evaluateBezier(piece.bezier.data(), double(i) / n, double(j) / n).position;
        Vec3d sample(samples[grid.offsets[q] + size_t(j) * (n + 1) + i]);
        worst = std::max(worst, length(sample - exact));
      }
    }
  }
  return worst / length(Vec3d(set.boundsMax) - Vec3d(set.boundsMin));
}

TEST(UniformGrid, SamplesThePlansUniformPieces) {
  for (const char* name : {"bigguy", "car", "armorguy"}) {
    const PatchSet set = loadPatches(name);
    for (int p : {1, 5, 16}) {
      SCOPED_TRACE(std::string(name) + ", p = " + std::to_string(p));
      TessellationOptions options;
      options.accuracy = Accuracy::uniformLevel(p);
      const TessellationPlan plan = planTessellation(set, options);
      UniformGrid grid;
      planUniformGrid(set, p, grid);
      ASSERT_EQ(grid.pieces.size(), plan.pieces.size());
      size_t levelMismatches = 0, basisMismatches = 0;
      for (size_t q = 0; q < plan.pieces.size(); ++q) {
        levelMismatches += grid.pieces[q].level != plan.pieces[q].level;
        const bool bezier = plan.pieces[q].kind == PieceKind::kInnermost;
        basisMismatches += (grid.pieces[q].basis == NetBasis::kBezier) != bezier;
      }
      EXPECT_EQ(levelMismatches, 0u);
      EXPECT_EQ(basisMismatches, 0u);
      std::vector<Vec3> samples(grid.samples());
      evaluateUniformGrid(set, grid, samples.data());
      // Float rounding only: B-spline weights here, the planner's float Bézier conversion there.
      EXPECT_LT(deviationFromPlan(set, grid, plan, samples), 1e-6);
    }
  }
}

// A grid object reused across models and levels, as a viewer's would be, equals a fresh one.
TEST(UniformGrid, ReusedGridEqualsAFreshOne) {
  const PatchSet bigguy = loadPatches("bigguy"), car = loadPatches("car");
  UniformGrid reused;
  for (auto [set, p] : {std::pair{&car, 64}, {&bigguy, 16}, {&car, 3}, {&bigguy, 64}}) {
    planUniformGrid(*set, p, reused);
    UniformGrid fresh;
    planUniformGrid(*set, p, fresh);
    EXPECT_TRUE(reused.pieces == fresh.pieces);
    ASSERT_EQ(reused.ringNets.size(), fresh.ringNets.size());
    EXPECT_EQ(0, std::memcmp(reused.ringNets.data(), fresh.ringNets.data(),
                             fresh.ringNets.size() * sizeof(ControlNet)));
    EXPECT_EQ(reused.offsets, fresh.offsets);
    EXPECT_EQ(reused.ringFirst, fresh.ringFirst);
  }
}

TEST(UniformGrid, LevelsOutsideTheRangeAreRefused) {
  const PatchSet car = loadPatches("car");
  UniformGrid grid;
  for (int p : {0, -3, 4097}) {
    try {
      planUniformGrid(car, p, grid);
      ADD_FAILURE() << "level " << p << " was accepted";
    } catch (const TesseraError& error) {
      EXPECT_NE(std::string(error.what()).find("level: must be in [1, 4096]"),
                std::string::npos)
          << error.what();
    }
  }
}

}  // namespace
}  // namespace tessera
