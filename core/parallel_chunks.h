// How finely the adaptive path cuts a loop for TBB: about four chunks a thread. Fixed chunks of
// 16 roots or 256 tiles ran a small request (the creased torus at 1e-3: 32 roots, ~300 tiles) as
// two uneven pieces, so the second core sat out stitching and triangulation; n/64 evened them but,
// on 2 cores, cut the torus into 32 one-root chunks whose steals cost more than they balanced
// (worse when the cores are far apart: bench/machine_load.h). Four a thread is n/64 on 16 cores,
// n/8 on 2; the upper limit keeps large requests' chunks as they were.
#pragma once

#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>

namespace tessera {

// The chunk size for a loop over n items: n / (4 · threads), within [least, most].
inline size_t chunkFor(size_t n, size_t least, size_t most) {
  const size_t parts = 4 * size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
  return std::clamp<size_t>(n / parts, least, most);
}

}  // namespace tessera
