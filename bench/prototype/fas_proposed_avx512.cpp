// The proposed kernel compiled with -mavx512f -mprefer-vector-width=512 (see CMakeLists.txt).
#include "bench/prototype/fas_proposed.h"

#define TESSERA_PROPOSED_NS proposed_avx512
#include "bench/prototype/fas_proposed_kernel.h"

namespace tessera::proposed {

void refineRingBlocksAvx512(const RingRules& rules, const float* blocks, int blockCount, int depth,
                            float* output) {
  proposed_avx512::refineRingBlocks(rules, blocks, blockCount, depth, output);
}

bool avx512Available() {
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
}

}  // namespace tessera::proposed
