// The paper's Table 2 rule for a uniform level p: rings are refined until ⌈log₂ p⌉ levels lie
// below the base face, and a piece at total depth d gets level max(p / 2^d, 1), so that every
// base face is sampled about p times along each side whatever its refinement.
#pragma once

#include <algorithm>
#include <cmath>

namespace tessera {

// FAS depth for a ring taken at Far level `ringLevel`.
inline int uniformRingDepth(int p, int ringLevel) {
  const int target = int(std::ceil(std::log2(double(p))));
  return std::max(0, target - ringLevel);
}

inline int uniformPieceLevel(int p, int depth) { return std::max(p >> std::min(depth, 30), 1); }

}  // namespace tessera
