// The block kernel compiled for AVX-512 (core/CMakeLists.txt adds the flags to this file only):
// a point of a block (48 floats) is three 64-byte vectors instead of six 32-byte ones.
#include "core/rings/fas_kernel_impl.h"

namespace tessera::fas_kernel {

void refineBlocksAvx512(const BlockJob& job, int begin, int end) {
  refineBlocks(job, begin, end);
}

// The kernel uses AVX-512F, and AVX-512VL for the 8-float halves of a point.
bool hasAvx512() {
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
}

}  // namespace tessera::fas_kernel
