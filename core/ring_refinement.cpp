#include "core/ring_refinement.h"

#include <cmath>

namespace tessera {

void emitRingPieces(const RingSet& rings, size_t r, int depth, RingPieces& pieces) {
  const cer::RingShape& shape = rings.shapes[r];
  const PatchDomain* sectorDomains = rings.sectorDomains.data() + rings.sectorOffsets[r];
  const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
  std::vector<float> levels;
  const float* innermost =
      forEachRingPatch(rings, r, depth, levels, [&](const ControlNet& net, PatchDomain domain, int level) {
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
