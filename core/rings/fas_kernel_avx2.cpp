// The block kernel for the baseline instruction set (TESSERA_SIMD_FLAGS: AVX2).
#include "core/rings/fas_kernel_impl.h"

namespace tessera::fas_kernel {

void refineBlocksAvx2(const BlockJob& job, int begin, int end) {
  refineBlocks(job, begin, end);
}

}  // namespace tessera::fas_kernel
