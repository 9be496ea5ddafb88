// OpenSubdiv's strongest CPU route to the refined points of Table 1 (paper §4.3, the [NLMD12]
// column is table-driven subdivision): Far refines the ring mesh uniformly once, the
// StencilTableFactory factorizes every refined vertex onto the 6n+1 control points, and
// Osd::OmpEvaluator applies the stencils of just the d·(12n+1) points that FAS writes to every
// ring. Rings are evaluated in chunks of R: one EvalStencils call covers R rings, each element
// being R rings' xyz side by side (structure of arrays over rings), so every stencil weight is
// loaded once per R rings and the inner loop is a long contiguous multiply-add.
#pragma once

#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/rings/cer_layout.h"

namespace tessera::bench {

// Compact stencil arrays in the raw form OmpEvaluator::EvalStencils takes; stencil
// s = (level - 1)·(12n+1) + p produces refined point p (CER order) of `level`.
struct RingStencils {
  std::vector<int> sizes, offsets, indices;
  std::vector<float> weights;
  int controlPoints = 0;          // 6n+1: every index refers to a point of the ring itself
  std::vector<int> refinedPoint;  // stencil s writes (level - 1)·(12n+1) + p; identity unless
                                  // reordered by balanceForStaticSchedule

  int count() const { return int(sizes.size()); }
};

// Refiner + factory + selection: everything OpenSubdiv needs before it can evaluate a ring.
// Throws std::runtime_error if Far's levels do not contain the CER refined sets.
RingStencils buildRingStencils(const ControlMesh& mesh, const cer::RingShape& shape, int depth);

// OmpEvaluator's loop over stencils has no schedule clause, so libgomp hands each of `threads`
// threads one contiguous run of stencils; in level order the last thread gets the deepest levels,
// whose stencils are the longest. This reorders the stencils so that every thread's run holds
// about the same number of weights (the output is then in the order given by refinedPoint).
RingStencils balanceForStaticSchedule(const RingStencils& stencils, int threads);

// The chunked layout: chunk c holds rings [cR, cR + m) (m = R except for a short last chunk);
// point i of its ring j is at xyz [firstRing·points·3 + i·3m + 3j]. `points` is 6n+1 for the
// source and the stencil count for the result.
size_t chunkedIndex(int points, int rings, int chunkRings, int ring, int point);

// Writes the tiled rings (ring r = distinct ring r % kDistinctRings) in the chunked layout.
void fillChunkedRings(const cer::RingShape& shape, const std::vector<float>& distinct, int rings,
                      int chunkRings, float* source);

// Applies every stencil to every ring, one OmpEvaluator::EvalStencils call per chunk.
void evalChunkedStencils(const RingStencils& stencils, const float* source, float* result,
                         int rings, int chunkRings);

}  // namespace tessera::bench
