// From a stored ring to surface pieces: FAS to a depth, then the 3n regular B-spline patches of
// every level (with the part of the base face each covers) and the innermost ring left over.
#pragma once

#include <vector>

#include "core/patch_set.h"

namespace tessera {

struct RingPieces {
  std::vector<ControlNet> bspline;  // absolute positions
  std::vector<PatchDomain> domains;
  std::vector<uint8_t> depths;      // FAS level (1..depth) each patch came from
  std::vector<float> innermostRing; // ring at `depth`, relative to the ring's centre
  std::vector<int> innermostSectors;           // the sectors the ring owns
  std::vector<PatchDomain> innermostDomains;  // their inner quads [0, 2^-depth]²
};

// Refines ring r to `depth` (>= 0) and appends its pieces to `pieces`.
void emitRingPieces(const RingSet& rings, size_t r, int depth, RingPieces& pieces);

}  // namespace tessera
