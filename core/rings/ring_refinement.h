// From a stored ring to surface pieces: FAS to a depth, then the 3n regular B-spline patches of
// every level (with the part of the base face each covers) and the innermost ring left over.
#pragma once

#include <cmath>
#include <vector>

#include "core/rings/fas_rules.h"
#include "core/rings/innermost_patch.h"
#include "core/rings/patch_set.h"
#include "core/rings/ring_patches.h"

namespace tessera {

struct RingPieces {
  std::vector<ControlNet> bspline;  // absolute positions
  std::vector<PatchDomain> domains;
  std::vector<uint8_t> depths;      // FAS level (1..depth) each patch came from
  std::vector<float> innermostRing; // ring at `depth`, relative to the ring's centre
  std::vector<int> innermostSectors;           // the sectors the ring owns
  std::vector<PatchDomain> innermostDomains;  // their inner quads [0, 2^-depth]²
};

// A walk's room, kept by the caller (one per thread) and grown as needed: the refined rings of
// every level, and where each patch's net points come from (the same at every level).
struct RingWalkScratch {
  std::vector<float> levels;
  std::vector<NetSource> sources;
};

// Refines ring r level by level into the scratch and calls visit(net, domain, level) for the
// kPatchesPerSector B-spline patches of every owned sector at every FAS level 1..depth, nets in
// absolute positions. Returns the innermost ring, relative to the ring's centre (the stored ring
// itself at depth 0). One walk for every consumer, so the planner, the uniform grid and the
// tests' piece lists cannot drift apart.
template <typename Visit>
const float* forEachRingPatch(const RingSet& rings, size_t r, int depth, RingWalkScratch& scratch,
                              Visit&& visit) {
  const RingRules rules = rings.rules(r);
  const cer::RingShape& shape = rules.shape;
  const Vec3 center = rings.centers[r];
  const PatchDomain* sectorDomains = rings.sectorDomains.data() + rings.sectorOffsets[r];
  const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
  const size_t refinedFloats = size_t(shape.refinedPointCount()) * 3;
  std::vector<float>& levels = scratch.levels;
  if (levels.size() < refinedFloats * depth) levels.resize(refinedFloats * depth);
  const float* innermost = rings.ringPoints(r);
  if (depth == 0) return innermost;
  const size_t patches = size_t(shape.sectors) * kPatchesPerSector;
  if (scratch.sources.size() < 16 * patches) scratch.sources.resize(16 * patches);
  for (int i = 0; i < shape.sectors; ++i) {
    for (int k = 0; owned[i] && k < kPatchesPerSector; ++k)
      sectorNetSources(rules, i, k, scratch.sources.data() + 16 * (kPatchesPerSector * i + k));
  }
  for (int level = 1; level <= depth; ++level) {
    float* refined = levels.data() + (level - 1) * refinedFloats;
    refineRingStep<3>(rules, innermost, refined);
    innermost = refined;
    const double size = std::ldexp(1.0, -level);
    for (int i = 0; i < shape.sectors; ++i) {
      if (!owned[i]) continue;
      for (int k = 0; k < kPatchesPerSector; ++k) {
        ControlNet net;
        gatherNet(refined, scratch.sources.data() + 16 * (kPatchesPerSector * i + k), net.data());
        for (Vec3& p : net) p += center;
        int x0, y0;
        sectorPatchOrigin(k, x0, y0);
        visit(net, sectorDomains[i].restrict(x0 * size, y0 * size, size), level);
      }
    }
  }
  return innermost;
}

// The pieces ring r yields at FAS depth `depth`: kPatchesPerSector per owned sector at every
// level, then one innermost piece per owned sector.
int ringPieceCount(const RingSet& rings, size_t r, int depth);

// The innermost Bézier net (ACC-1, innermost_patch.h) of every owned sector, in sector order and
// absolute positions, from the innermost ring forEachRingPatch returned (relative to `center`):
// visit(sector, net). The EV's limit point, which every net shares and which costs O(valence),
// is computed once for the ring, not once per sector.
template <typename Visit>
void forEachInnermostNet(const RingRules& rules, const float* innermost, Vec3 center, const uint8_t* owned,
                         Visit visit) {
  auto fetch = [innermost](int index) {
    return Vec3(innermost[3 * index], innermost[3 * index + 1], innermost[3 * index + 2]);
  };
  const Vec3 limit = extraordinaryLimit<Vec3>(rules, fetch);
  for (int sector = 0; sector < rules.shape.sectors; ++sector) {
    if (!owned[sector]) continue;
    Vec3 net[16];
    innermostBezier<Vec3>(rules, sector, fetch, net, &limit);
    for (Vec3& p : net) p += center;
    visit(sector, net);
  }
}

// Refines ring r to `depth` (>= 0) and appends its pieces to `pieces`.
void emitRingPieces(const RingSet& rings, size_t r, int depth, RingPieces& pieces);

}  // namespace tessera
