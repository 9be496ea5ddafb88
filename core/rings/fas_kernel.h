// The CPU block kernel of refineRingBlocks (fas.cpp), compiled once per instruction set:
// fas_kernel_avx2.cpp is the baseline every x86-64 build of Tessera runs on,
// fas_kernel_avx512.cpp the same source for AVX-512 CPUs, chosen at run time by fas.cpp.
#pragma once

#include <cstddef>

#include "core/rings/fas_step_program.h"

namespace tessera::fas_kernel {

// A contiguous range of ring blocks refined by one thread. `ringBuffer` holds two refined
// blocks (64-byte aligned) the thread owns. An output aligned to the vector size is written
// with non-temporal stores, fenced before the kernel returns.
struct BlockJob {
  const StepProgram* program;
  const float* blocks;  // [block][point][xyz][lane]
  float* output;        // [block][level][point][xyz][lane]
  size_t ringFloats, refinedFloats;
  int depth;
  float* ringBuffer[2];
};

void refineBlocksAvx2(const BlockJob& job, int begin, int end);
void refineBlocksAvx512(const BlockJob& job, int begin, int end);  // only where hasAvx512()
bool hasAvx512();

}  // namespace tessera::fas_kernel
