// Dyadic squares: exact powers of two without a call into libm (tile and node sizes, root
// coordinates at scale 2^kRootBits, and the scaling of a point into a node's square are all
// multiplications by 2^e, done millions of times a request), and where a sub-square lies.
#pragma once

#include <bit>
#include <cstdint>

namespace tessera {

// 2^e for normal doubles (−1022 ≤ e ≤ 1023): the exponent field set directly.
constexpr double exp2i(int e) { return std::bit_cast<double>(uint64_t(1023 + e) << 52); }

// The sides of a square that its sub-square (x, y), `depth` levels down, lies on: bit k for side
// k (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0, the order of bezier_net.h's kSideIndex).
constexpr uint8_t sidesTouched(uint64_t x, uint64_t y, int depth) {
  const uint64_t last = (uint64_t(1) << depth) - 1;
  return uint8_t((y == 0) | (x == last) << 1 | (y == last) << 2 | (x == 0) << 3);
}

}  // namespace tessera
