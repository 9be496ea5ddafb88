// FAS on CER rings against OpenSubdiv Far refining the very same ring mesh, level by level.
#include "core/rings/fas.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/base/error.h"
#include "reference/far_reference.h"
#include "reference/ring_meshes.h"

namespace tessera {
namespace {

struct RingCase {
  int sectors;
  bool open;
  std::vector<uint8_t> sharpSpokes;
  bool cornerEv;
  int depth;
};

std::vector<float> ringPointsOf(const ControlMesh& mesh) {
  std::vector<float> ring;
  for (const Vec3& p : mesh.positions) ring.insert(ring.end(), {p.x, p.y, p.z});
  return ring;
}

double extentOf(const std::vector<float>& ring) {
  double extent = 0;
  for (float c : ring) extent = std::max(extent, double(std::fabs(c)));
  return extent;
}

void expectFasMatchesFar(const RingCase& c, uint32_t seed) {
  cer::RingShape shape{c.sectors, c.open};
  std::vector<uint8_t> sharp = c.sharpSpokes;
  sharp.resize(shape.spokeCount(), 0);
  ControlMesh mesh = testing::makeRingMesh(shape, seed, sharp, c.cornerEv);
  RingRules rules = makeRingRules(shape, sharp.data(), c.cornerEv);
  std::vector<float> ring = ringPointsOf(mesh);
  std::vector<float> levels = refineRing(rules, ring.data(), c.depth);
  testing::FarRefinement far = testing::FarRefinement::uniform(mesh, c.depth);

  const double tolerance = 1e-6 * extentOf(ring);
  const int refinedCount = shape.refinedPointCount();
  Index ev = 0, spoke = cer::ringIndex(0, cer::kE);
  for (int level = 1; level <= c.depth; ++level) {
    testing::FarRingLevel reference = testing::farRingLevel(far, level, ev, spoke);
    ASSERT_EQ(int(reference.refinedPoints.size()), refinedCount) << "level " << level;
    double worst = 0;
    for (int p = 0; p < refinedCount; ++p) {
      const float* mine = &levels[(size_t(level - 1) * refinedCount + p) * 3];
      Vec3d difference = Vec3d(Vec3(mine[0], mine[1], mine[2])) - reference.refinedPoints[p];
      worst = std::max(worst, length(difference));
    }
    EXPECT_LE(worst, tolerance) << "n=" << c.sectors << (c.open ? " open" : "") << " level "
                                << level;
    ev = reference.ev;
    spoke = reference.firstSpoke;
  }
}

TEST(Fas, MatchesOpenSubdivAtEveryLevelForSmoothRings) {
  for (int n : {2, 3, 4, 5, 6, 7, 8, 9, 10}) expectFasMatchesFar({n, false, {}, false, 6}, 100 + n);
  expectFasMatchesFar({16, false, {}, false, 5}, 116);
  expectFasMatchesFar({64, false, {}, false, 4}, 164);
}

TEST(Fas, MatchesOpenSubdivForCreaseDartAndCornerRings) {
  expectFasMatchesFar({5, false, {1, 0, 1, 0, 0}, false, 5}, 1);  // crease through the EV
  expectFasMatchesFar({6, false, {1, 0, 0, 1, 0, 0}, false, 5}, 2);
  expectFasMatchesFar({4, false, {1, 1, 0, 0}, false, 5}, 3);        // bent crease, valence 4
  expectFasMatchesFar({5, false, {0, 0, 1, 0, 0}, false, 5}, 4);     // dart
  expectFasMatchesFar({6, false, {1, 0, 1, 0, 1, 0}, false, 5}, 5);  // three creases: corner
  expectFasMatchesFar({5, false, {}, true, 5}, 6);                   // tagged corner
}

TEST(Fas, MatchesOpenSubdivForBoundaryRings) {
  for (int k : {1, 2, 3, 4, 5}) expectFasMatchesFar({k, true, {}, false, 5}, 200 + k);
  expectFasMatchesFar({4, true, {0, 0, 1, 0, 0}, false, 5}, 210);  // boundary + interior crease
}

// refineRingBlocks (decoded step program, SIMD blocks, `kernel`'s instruction set) against the
// scalar per-point path, bit for bit, for every lane of a padded last block.
void expectBlocksEqualScalar(const RingCase& c, FasKernel kernel) {
  cer::RingShape shape{c.sectors, c.open};
  std::vector<uint8_t> sharp = c.sharpSpokes;
  sharp.resize(shape.spokeCount(), 0);
  RingRules rules = makeRingRules(shape, sharp.data(), c.cornerEv);
  const int count = 2 * kFasLanes + 3;
  std::vector<float> rings;
  for (int r = 0; r < count; ++r) {
    auto ring = ringPointsOf(testing::makeRingMesh(shape, 300 + r, sharp, c.cornerEv));
    rings.insert(rings.end(), ring.begin(), ring.end());
  }
  std::vector<float> blocks = packRingBlocks(shape, rings.data(), count);
  const int blockCount = int(blocks.size() / ringBlockFloats(shape));
  const size_t levelFloats = refinedBlockFloats(shape);
  // 64-byte aligned (streaming stores) unless `offset` shifts it: both store paths are checked.
  for (size_t offset : {size_t(0), size_t(1)}) {
    std::vector<float> storage(size_t(blockCount) * c.depth * levelFloats + 16 + offset);
    auto base = reinterpret_cast<uintptr_t>(storage.data());
    float* output = storage.data() + ((64 - base % 64) % 64) / sizeof(float) + offset;
    refineRingBlocks(rules, blocks.data(), blockCount, c.depth, output, kernel);
    for (int r = 0; r < count; ++r) {
      auto scalar =
          refineRing(rules, rings.data() + size_t(r) * shape.ringPointCount() * 3, c.depth);
      int block = r / kFasLanes, lane = r % kFasLanes;
      for (int level = 0; level < c.depth; ++level) {
        const float* levelBlock = output + (size_t(block) * c.depth + level) * levelFloats;
        for (int p = 0; p < shape.refinedPointCount(); ++p) {
          for (int k = 0; k < 3; ++k) {
            ASSERT_EQ(levelBlock[p * kFasBlockFloats + k * kFasLanes + lane],
                      scalar[(size_t(level) * shape.refinedPointCount() + p) * 3 + k])
                << "n=" << c.sectors << (c.open ? " open" : "") << " ring " << r << " level "
                << level << " point " << p << " offset " << offset;
          }
        }
      }
    }
  }
}

void expectBlocksEqualScalarForEveryRingKind(FasKernel kernel) {
  for (int n : {2, 3, 4, 5, 6, 7, 8, 9, 10})
    expectBlocksEqualScalar({n, false, {}, false, 4}, kernel);
  expectBlocksEqualScalar({16, false, {}, false, 3}, kernel);
  expectBlocksEqualScalar({64, false, {}, false, 2}, kernel);              // 16-bit packed indices
  expectBlocksEqualScalar({5, false, {1, 0, 1, 0, 0}, false, 4}, kernel);  // crease
  expectBlocksEqualScalar({5, false, {0, 0, 1, 0, 0}, false, 4}, kernel);  // dart
  expectBlocksEqualScalar({6, false, {1, 0, 1, 0, 1, 0}, false, 4}, kernel);  // three creases
  expectBlocksEqualScalar({5, false, {}, true, 4}, kernel);                   // tagged corner
  for (int k : {1, 2, 3, 5}) expectBlocksEqualScalar({k, true, {}, false, 4}, kernel);
  expectBlocksEqualScalar({4, true, {0, 0, 1, 0, 0}, false, 4}, kernel);  // boundary + crease
}

TEST(Fas, BlockedSimdPathEqualsScalarPathBitForBit) {
  expectBlocksEqualScalarForEveryRingKind(FasKernel::kAvx2);
}

TEST(Fas, BlockedAvx512PathEqualsScalarPathBitForBit) {
  if (!fasKernelAvailable(FasKernel::kAvx512)) GTEST_SKIP() << "this CPU has no AVX-512";
  expectBlocksEqualScalarForEveryRingKind(FasKernel::kAvx512);
}

TEST(Fas, DefaultBlockPathUsesAnAvailableKernel) {
  EXPECT_TRUE(fasKernelAvailable(fastestFasKernel()));
  if (!fasKernelAvailable(FasKernel::kAvx512)) {
    cer::RingShape shape{3, false};
    float dummy = 0;
    EXPECT_THROW(refineRingBlocks(makeRingRules(shape, nullptr, false), &dummy, 0, 1, &dummy,
                                  FasKernel::kAvx512),
                 TesseraError);
  }
}

TEST(Fas, RefinesToDepthTwentyFourWithoutLosingTheRing) {
  cer::RingShape shape{5, false};
  RingRules rules = makeRingRules(shape, nullptr, false);
  auto ring = ringPointsOf(testing::makeRingMesh(shape, 7));
  auto levels = refineRing(rules, ring.data(), 24);
  const int refinedCount = shape.refinedPointCount();
  // The innermost ring contracts toward the limit point: its spread shrinks like λ^m.
  auto spread = [&](int level) {
    double s = 0;
    const float* base = &levels[size_t(level - 1) * refinedCount * 3];
    for (int p = 1; p < shape.ringPointCount(); ++p) {
      for (int c = 0; c < 3; ++c) s = std::max(s, double(std::fabs(base[3 * p + c] - base[c])));
    }
    return s;
  };
  EXPECT_LT(spread(24), 1e-4 * spread(1));
  for (float v : levels) ASSERT_TRUE(std::isfinite(v));
}

}  // namespace
}  // namespace tessera
