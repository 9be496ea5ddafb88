// From a stored ring to surface pieces: FAS to a depth, then the 3n regular B-spline patches of
// every level (with the part of the base face each covers) and the innermost ring left over.
#pragma once

#include <cmath>
#include <vector>

#include "core/fas_rules.h"
#include "core/patch_set.h"
#include "core/ring_patches.h"

namespace tessera {

struct RingPieces {
  std::vector<ControlNet> bspline;  // absolute positions
  std::vector<PatchDomain> domains;
  std::vector<uint8_t> depths;      // FAS level (1..depth) each patch came from
  std::vector<float> innermostRing; // ring at `depth`, relative to the ring's centre
  std::vector<int> innermostSectors;           // the sectors the ring owns
  std::vector<PatchDomain> innermostDomains;  // their inner quads [0, 2^-depth]²
};

// Refines ring r level by level into `levels` (the caller's scratch, grown as needed) and calls
// visit(net, domain, level) for the kPatchesPerSector B-spline patches of every owned sector at
// every FAS level 1..depth, nets in absolute positions. Returns the innermost ring, relative to
// the ring's centre (the stored ring itself at depth 0). One walk for every consumer, so the
// planner and the tests' piece lists cannot drift apart.
template <typename Visit>
const float* forEachRingPatch(const RingSet& rings, size_t r, int depth, std::vector<float>& levels,
                              Visit&& visit) {
  const RingRules rules = rings.rules(r);
  const cer::RingShape& shape = rules.shape;
  const Vec3 center = rings.centers[r];
  const PatchDomain* sectorDomains = rings.sectorDomains.data() + rings.sectorOffsets[r];
  const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
  const size_t refinedFloats = size_t(shape.refinedPointCount()) * 3;
  if (levels.size() < refinedFloats * depth) levels.resize(refinedFloats * depth);
  const float* innermost = rings.ringPoints(r);
  for (int level = 1; level <= depth; ++level) {
    float* refined = levels.data() + (level - 1) * refinedFloats;
    refineRingStep<3>(rules, innermost, refined);
    innermost = refined;
    const double size = std::ldexp(1.0, -level);
    for (int i = 0; i < shape.sectors; ++i) {
      if (!owned[i]) continue;
      for (int k = 0; k < kPatchesPerSector; ++k) {
        ControlNet net;
        sectorPatchNet(rules, refined, i, k, net.data());
        for (Vec3& p : net) p += center;
        int x0, y0;
        sectorPatchOrigin(k, x0, y0);
        visit(net, sectorDomains[i].restrict(x0 * size, y0 * size, size), level);
      }
    }
  }
  return innermost;
}

// Refines ring r to `depth` (>= 0) and appends its pieces to `pieces`.
void emitRingPieces(const RingSet& rings, size_t r, int depth, RingPieces& pieces);

}  // namespace tessera
