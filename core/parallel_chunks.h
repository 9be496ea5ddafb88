// How finely the adaptive path cuts a loop for TBB. A small request (the creased torus at 1e-3:
// 32 roots, ~300 tiles) cut into fixed chunks of 16 roots or 256 tiles ran as two uneven pieces,
// so the second core sat out stitching and triangulation; chunks of n/64 keep four or more a core
// on 16 cores, and the upper limit keeps large requests' chunks as they were.
#pragma once

#include <algorithm>
#include <cstddef>

namespace tessera {

// The chunk size for a loop over n items: n / 64, within [least, most].
inline size_t chunkFor(size_t n, size_t least, size_t most) {
  return std::clamp<size_t>(n / 64, least, most);
}

}  // namespace tessera
