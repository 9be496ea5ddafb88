#include "core/rings/ring_refinement.h"

#include <algorithm>
#include <cmath>

#include "core/rings/innermost_patch.h"

namespace tessera {

int ringPieceCount(const RingSet& rings, size_t r, int depth) {
  const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
  const int sectors = int(
      std::count_if(owned, owned + rings.shapes[r].sectors, [](uint8_t o) { return o != 0; }));
  return sectors * (kPatchesPerSector * depth + 1);
}

void emitRingPieces(const RingSet& rings, size_t r, int depth, RingPieces& pieces) {
  const cer::RingShape& shape = rings.shapes[r];
  const PatchDomain* sectorDomains = rings.sectorDomains.data() + rings.sectorOffsets[r];
  const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
  RingWalkScratch scratch;
  const float* innermost =
      forEachRingPatch(rings, r, depth, scratch, [&](const ControlNet& net, PatchDomain domain, int level) {
        pieces.bspline.push_back(net);
        pieces.domains.push_back(domain);
        pieces.depths.push_back(static_cast<uint8_t>(level));
      });
  pieces.innermostRing.insert(pieces.innermostRing.end(), innermost,
                              innermost + 3 * shape.ringPointCount());
  const double size = std::ldexp(1.0, -depth);
  for (int i = 0; i < shape.sectors; ++i) {
    if (!owned[i]) continue;
    pieces.innermostSectors.push_back(i);
    pieces.innermostDomains.push_back(sectorDomains[i].restrict(0, 0, size));
  }
}

}  // namespace tessera
