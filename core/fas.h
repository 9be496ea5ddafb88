// CER-based feature-adaptive subdivision on the CPU (paper §4.2): rings are refined level by
// level in a small ring buffer that stays in cache, connectivity recovered by index arithmetic
// (fas_rules.h). Rings of one shape are processed kFasLanes at a time, their points interleaved
// so that every stencil is a short SIMD loop, and blocks are spread over all cores.
#pragma once

#include <cstddef>
#include <vector>

#include "core/fas_rules.h"

namespace tessera {

inline constexpr int kFasLanes = 8;
inline constexpr int kFasBlockFloats = 3 * kFasLanes;  // one point of a block: xyz × lanes

// Block layout: [block][point][coordinate][lane]. A ring r of a packed array lives in block
// r / kFasLanes, lane r % kFasLanes.
size_t ringBlockFloats(const cer::RingShape& shape);     // one block of rings
size_t refinedBlockFloats(const cer::RingShape& shape);  // one block of one level's refined sets

// Packs `count` rings given one after another (ringPointCount × xyz each) into blocks; the last
// block is padded by repeating its last ring.
std::vector<float> packRingBlocks(const cer::RingShape& shape, const float* rings, int count);

// Refines every block to `depth` and writes the refined set (12n+1 points) of every level:
// output[block][level - 1][point][coordinate][lane]. Uses all cores.
void refineRingBlocks(const RingRules& rules, const float* blocks, int blockCount, int depth,
                      float* output);

// One ring (xyz per point), each level's refined set appended to the result:
// result[(level - 1) * refinedPointCount * 3 + 3 * point + coordinate].
std::vector<float> refineRing(const RingRules& rules, const float* ring, int depth);

}  // namespace tessera
