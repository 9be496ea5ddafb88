// The CUDA kernel's algorithm run on the CPU: gpu/cuda/warp_fas.h compiled by the host compiler,
// driven like fas_kernel.cu drives it (same plan, same shared-memory layout, same grid-stride
// ring assignment and output offsets), with the 32 lanes of a warp iterated one after another
// between the points where the kernel calls __syncwarp(). Runs on every machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>

#include "gpu/cuda/cuda_fas.h"
#include "gpu/cuda/warp_fas.h"
#include "tests/cuda/ring_batches.h"

namespace tessera::cuda {
namespace {

using LaneOrder = std::array<int, kWarpSize>;

LaneOrder forwardLanes() {
  LaneOrder order;
  std::iota(order.begin(), order.end(), 0);
  return order;
}

LaneOrder reversedLanes() {
  LaneOrder order = forwardLanes();
  std::reverse(order.begin(), order.end());
  return order;
}

LaneOrder shuffledLanes(uint32_t seed) {
  LaneOrder order = forwardLanes();
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  return order;
}

// The grid of fas_kernel.cu, executed sequentially: blocks one after another; within a block all
// warps advance in lockstep, phase by phase, so that two warps sharing buffer space would corrupt
// each other; within a phase the lanes run in `order`. Untouched output stays NaN.
std::vector<float> simulateWarpFas(const RingRules& rules, int depth, int count, const float* rings,
                                   int blocks, const LaneOrder& order) {
  const WarpFasPlan plan = planWarpFas(rules.shape, depth);
  const WarpFasLayout& layout = plan.layout;
  const float poison = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> output(cudaFasOutputFloats(rules.shape, depth, count), poison);
  std::vector<float> scratch(plan.scratchFloats(blocks), poison);

  const WarpStepImage image = makeWarpStepImage(rules);
  const WarpStepProgram step = bindWarpStep(image, image.words.data());
  for (int block = 0; block < blocks; ++block) {
    std::vector<float> shared((plan.sharedBytes() + sizeof(float) - 1) / sizeof(float), poison);
    std::vector<float*> buffers(plan.warpsPerBlock);
    std::vector<int> ringOf(plan.warpsPerBlock);
    for (int warp = 0; warp < plan.warpsPerBlock; ++warp) {
      buffers[warp] = plan.sharedBuffers ? plan.sharedWarpBuffer(shared.data(), warp)
                                         : plan.scratchWarpBuffer(scratch.data(), block, warp);
      ringOf[warp] = plan.firstRing(block, warp);
    }
    // Runs `phase(warp, lane)` for every warp that still has a ring, lanes in `order`.
    auto eachLane = [&](auto phase) {
      for (int warp = 0; warp < plan.warpsPerBlock; ++warp) {
        if (ringOf[warp] >= count) continue;
        for (int lane : order) phase(warp, lane);
      }
    };
    while (*std::min_element(ringOf.begin(), ringOf.end()) < count) {
      eachLane([&](int w, int lane) {
        warpLoadRing(layout, lane, rings + layout.inputOffset(ringOf[w]), buffers[w]);
      });
      for (int level = 0; level < depth; ++level) {
        eachLane([&](int w, int lane) { warpFacePass(step, layout, lane, buffers[w]); });
        eachLane([&](int w, int lane) { warpEdgeVertexPass(step, layout, lane, buffers[w]); });
        eachLane([&](int w, int lane) {
          warpStoreLevel(layout, lane, buffers[w],
                         output.data() + layout.outputOffset(ringOf[w], level));
        });
      }
      for (int& ring : ringOf) ring += plan.ringStride(blocks);
    }
  }
  return output;
}

// Enough rings that every warp of a 2-block grid takes two, and some a third.
int ringsForTwoRounds(const cer::RingShape& shape) {
  return 2 * planWarpFas(shape, 1).ringStride(2) + 3;
}

void expectSimulationEqualsRefineRing(const testing::RingKind& kind, int depth,
                                      const LaneOrder& order, uint32_t seed) {
  const cer::RingShape shape = kind.shape();
  const std::vector<uint8_t> flags = kind.flags();
  const RingRules rules = makeRingRules(shape, flags.data(), kind.cornerEv);
  const int count = ringsForTwoRounds(shape);
  const std::vector<float> rings = testing::ringBatch(kind, count, seed);
  const std::vector<float> expected = testing::cpuReference(rules, depth, count, rings);
  const std::vector<float> simulated = simulateWarpFas(rules, depth, count, rings.data(), 2, order);
  ASSERT_EQ(simulated.size(), expected.size());
  const WarpFasLayout layout = makeWarpFasLayout(shape, depth);
  for (int ring = 0; ring < count; ++ring) {
    for (int level = 0; level < depth; ++level) {
      const size_t base = layout.outputOffset(ring, level);
      // memcmp: bit-for-bit, and an unwritten (NaN) float never compares equal.
      ASSERT_EQ(
          std::memcmp(&simulated[base], &expected[base], layout.refinedFloats * sizeof(float)), 0)
          << "n=" << shape.sectors << (shape.open ? " open" : "") << " ring " << ring << " level "
          << level + 1;
    }
  }
}

TEST(WarpFasSimulation, MatchesRefineRingBitForBitForSmoothRings) {
  for (int n : {2, 3, 4, 5, 6, 7, 8, 9, 10, 16, 31, 32, 33, 64}) {
    expectSimulationEqualsRefineRing({n}, 5, forwardLanes(), 100 + n);
  }
}

TEST(WarpFasSimulation, MatchesRefineRingAtDepthTwentyFour) {
  expectSimulationEqualsRefineRing({5}, kMaxCudaFasDepth, forwardLanes(), 7);
}

TEST(WarpFasSimulation, MatchesRefineRingForCreaseDartCornerAndBoundaryRings) {
  const std::vector<testing::RingKind> kinds = {
      {5, false, {1, 0, 1, 0, 0}},     // crease through the EV
      {4, false, {1, 1, 0, 0}},        // bent crease, valence 4
      {5, false, {0, 0, 1, 0, 0}},     // dart
      {6, false, {1, 0, 1, 0, 1, 0}},  // three creases: corner
      {5, false, {}, true},            // tagged corner
      {1, true},
      {3, true},
      {5, true},
      {4, true, {0, 0, 1, 0, 0}},                // boundary + interior crease
      {40, false, std::vector<uint8_t>(40, 1)},  // every spoke sharp, more spokes than lanes
  };
  for (size_t k = 0; k < kinds.size(); ++k) {
    expectSimulationEqualsRefineRing(kinds[k], 5, forwardLanes(), 200 + uint32_t(k));
  }
}

TEST(WarpFasSimulation, GlobalScratchPathForValenceAbove64MatchesRefineRing) {
  ASSERT_FALSE(planWarpFas({kMaxSharedValence + 1, false}, 3).sharedBuffers);
  expectSimulationEqualsRefineRing({kMaxSharedValence + 1}, 3, forwardLanes(), 65);
  expectSimulationEqualsRefineRing({100}, 3, reversedLanes(), 100);
  expectSimulationEqualsRefineRing({70, true, {0, 1}}, 3, forwardLanes(), 70);
}

// Within a phase no lane may read what another lane writes; if one did, the result would depend
// on the order the lanes run in.
TEST(WarpFasSimulation, ResultDoesNotDependOnLaneOrder) {
  for (int n : {3, 7, 33, 64}) {
    expectSimulationEqualsRefineRing({n}, 3, reversedLanes(), 300 + n);
    expectSimulationEqualsRefineRing({n}, 3, shuffledLanes(uint32_t(n)), 300 + n);
  }
  expectSimulationEqualsRefineRing({6, true, {0, 0, 1}}, 3, shuffledLanes(9), 309);
}

TEST(WarpFasPlan, FitsSharedMemoryWithoutOptInUpToValence64) {
  for (bool open : {false, true}) {
    for (int n = 1; n <= kMaxSharedValence; ++n) {
      if (!open && n < 2) continue;
      WarpFasPlan plan = planWarpFas({n, open}, 6);
      EXPECT_TRUE(plan.sharedBuffers) << n;
      EXPECT_GE(plan.warpsPerBlock, 1) << n;
      EXPECT_LE(plan.warpsPerBlock, kMaxWarpsPerBlock) << n;
      EXPECT_LE(plan.sharedBytes(), size_t(kSharedBytesPerBlock)) << n;
    }
  }
  // Table 1's valences keep a full block of 8 warps.
  for (int n = 3; n <= 10; ++n)
    EXPECT_EQ(planWarpFas({n, false}, 6).warpsPerBlock, kMaxWarpsPerBlock);
}

TEST(WarpFasPlan, LayoutIsRefineRingsLayout) {
  const cer::RingShape shape{5, false};
  const WarpFasLayout layout = makeWarpFasLayout(shape, 4);
  EXPECT_EQ(layout.ringFloats, 3 * (6 * 5 + 1));
  EXPECT_EQ(layout.refinedFloats, 3 * (12 * 5 + 1));
  EXPECT_EQ(layout.outputOffset(2, 3), size_t(2 * 4 + 3) * 3 * 61);
  EXPECT_EQ(cudaFasOutputFloats(shape, 4, 3), layout.outputOffset(3, 0));
}

}  // namespace
}  // namespace tessera::cuda
