// CER-based feature-adaptive subdivision on the CPU (paper §4.2): rings are refined level by
// level in a small ring buffer that stays in cache, connectivity recovered by index arithmetic
// (fas_rules.h, decoded once per ring shape for the block path: fas_step_program.h). Rings of
// one shape are processed kFasLanes at a time, their points interleaved so that every stencil
// is a short SIMD loop (fas_kernel.h), and blocks are spread over all cores.
#pragma once

#include <cstddef>
#include <vector>

#include "core/rings/fas_rules.h"

namespace tessera {

inline constexpr int kFasLanes = 16;
inline constexpr int kFasBlockFloats = 3 * kFasLanes;  // one point of a block: xyz × lanes

// Block layout: [block][point][coordinate][lane]. A ring r of a packed array lives in block
// r / kFasLanes, lane r % kFasLanes.
size_t ringBlockFloats(const cer::RingShape& shape);     // one block of rings
size_t refinedBlockFloats(const cer::RingShape& shape);  // one block of one level's refined sets

// Packs `count` rings given one after another (ringPointCount × xyz each) into blocks; the last
// block is padded by repeating its last ring.
std::vector<float> packRingBlocks(const cer::RingShape& shape, const float* rings, int count);

// The instruction set of the block kernel: AVX2 is the baseline every build runs on; AVX-512
// is used where the CPU has it. Both give the same bits.
enum class FasKernel { kAvx2, kAvx512 };
bool fasKernelAvailable(FasKernel kernel);
FasKernel fastestFasKernel();

// Refines every block to `depth` and writes the refined set (12n+1 points) of every level:
// output[block][level - 1][point][coordinate][lane]. Uses all cores and fastestFasKernel().
// The step's operands are decoded once per call (fas_step_program.h). A 64-byte aligned output
// is written with non-temporal stores, past the cache.
void refineRingBlocks(const RingRules& rules, const float* blocks, int blockCount, int depth,
                      float* output);
// The same with a given kernel (tests compare them); throws TesseraError (kUnsupported) when
// this CPU lacks it.
void refineRingBlocks(const RingRules& rules, const float* blocks, int blockCount, int depth,
                      float* output, FasKernel kernel);

// One ring (xyz per point), each level's refined set appended to the result:
// result[(level - 1) * refinedPointCount * 3 + 3 * point + coordinate].
std::vector<float> refineRing(const RingRules& rules, const float* ring, int depth);

}  // namespace tessera
