// PROTOTYPE: core/fas.cpp's refineRingBlocks with the changes proposed in bench/RESULTS.md,
// same arguments and output layout; tessera-bench runs it as BM_ProposedCer to measure them.
#pragma once

#include "core/fas.h"

namespace tessera::proposed {

void refineRingBlocks(const RingRules& rules, const float* blocks, int blockCount, int depth,
                      float* output);

// The same kernel compiled for AVX-512 (same 8-lane layout: a 24-float point is one 16-float
// and one 8-float vector instead of three 8-float ones). Only call where avx512Available().
void refineRingBlocksAvx512(const RingRules& rules, const float* blocks, int blockCount, int depth,
                            float* output);
bool avx512Available();

}  // namespace tessera::proposed
