// Exact powers of two without a call into libm: tile and node sizes, root coordinates at scale
// 2^kRootBits, and the scaling of a point into a node's square are all multiplications by 2^e,
// done millions of times a request.
#pragma once

#include <bit>
#include <cstdint>

namespace tessera {

// 2^e for normal doubles (−1022 ≤ e ≤ 1023): the exponent field set directly.
constexpr double exp2i(int e) { return std::bit_cast<double>(uint64_t(1023 + e) << 52); }

}  // namespace tessera
