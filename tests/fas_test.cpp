// FAS on CER rings against OpenSubdiv Far refining the very same ring mesh, level by level.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/fas.h"
#include "tests/support/far_reference.h"
#include "tests/support/ring_meshes.h"

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
    EXPECT_LE(worst, tolerance) << "n=" << c.sectors << (c.open ? " open" : "") << " level " << level;
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
  expectFasMatchesFar({5, false, {1, 0, 1, 0, 0}, false, 5}, 1);   // crease through the EV
  expectFasMatchesFar({6, false, {1, 0, 0, 1, 0, 0}, false, 5}, 2);
  expectFasMatchesFar({4, false, {1, 1, 0, 0}, false, 5}, 3);      // bent crease, valence 4
  expectFasMatchesFar({5, false, {0, 0, 1, 0, 0}, false, 5}, 4);   // dart
  expectFasMatchesFar({6, false, {1, 0, 1, 0, 1, 0}, false, 5}, 5);  // three creases: corner
  expectFasMatchesFar({5, false, {}, true, 5}, 6);                 // tagged corner
}

TEST(Fas, MatchesOpenSubdivForBoundaryRings) {
  for (int k : {1, 2, 3, 4, 5}) expectFasMatchesFar({k, true, {}, false, 5}, 200 + k);
  expectFasMatchesFar({4, true, {0, 0, 1, 0, 0}, false, 5}, 210);  // boundary + interior crease
}

TEST(Fas, BlockedSimdPathEqualsScalarPathBitForBit) {
  for (int n : {3, 5, 7}) {
    cer::RingShape shape{n, false};
    RingRules rules = makeRingRules(shape, nullptr, false);
    const int count = 2 * kFasLanes + 3, depth = 4;
    std::vector<float> rings;
    for (int r = 0; r < count; ++r) {
      auto ring = ringPointsOf(testing::makeRingMesh(shape, 300 + r));
      rings.insert(rings.end(), ring.begin(), ring.end());
    }
    std::vector<float> blocks = packRingBlocks(shape, rings.data(), count);
    int blockCount = int(blocks.size() / ringBlockFloats(shape));
    std::vector<float> output(size_t(blockCount) * depth * refinedBlockFloats(shape));
    refineRingBlocks(rules, blocks.data(), blockCount, depth, output.data());
    for (int r = 0; r < count; ++r) {
      auto scalar = refineRing(rules, rings.data() + size_t(r) * shape.ringPointCount() * 3, depth);
      int block = r / kFasLanes, lane = r % kFasLanes;
      for (int level = 0; level < depth; ++level) {
        const float* levelBlock = output.data() + (size_t(block) * depth + level) * refinedBlockFloats(shape);
        for (int p = 0; p < shape.refinedPointCount(); ++p) {
          for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(levelBlock[p * kFasBlockFloats + c * kFasLanes + lane],
                      scalar[(size_t(level) * shape.refinedPointCount() + p) * 3 + c])
                << "ring " << r << " level " << level << " point " << p;
          }
        }
      }
    }
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
