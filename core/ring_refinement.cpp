#include "core/ring_refinement.h"

#include <cmath>

#include "core/fas.h"
#include "core/ring_patches.h"

namespace tessera {

void emitRingPieces(const RingSet& rings, size_t r, int depth, RingPieces& pieces) {
  const RingRules rules = rings.rules(r);
  const cer::RingShape& shape = rules.shape;
  const Vec3 center = rings.centers[r];
  const PatchDomain* sectorDomains = rings.sectorDomains.data() + rings.sectorOffsets[r];
  const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
  std::vector<float> levels = refineRing(rules, rings.ringPoints(r), depth);
  const size_t refinedFloats = size_t(shape.refinedPointCount()) * 3;
  for (int level = 1; level <= depth; ++level) {
    const float* refined = levels.data() + (level - 1) * refinedFloats;
    const double size = std::ldexp(1.0, -level);
    for (int i = 0; i < shape.sectors; ++i) {
      if (!owned[i]) continue;
      for (int k = 0; k < kPatchesPerSector; ++k) {
        ControlNet net;
        sectorPatchNet(rules, refined, i, k, net.data());
        for (Vec3& p : net) p += center;
        int x0, y0;
        sectorPatchOrigin(k, x0, y0);
        pieces.bspline.push_back(net);
        pieces.domains.push_back(sectorDomains[i].restrict(x0 * size, y0 * size, size));
        pieces.depths.push_back(static_cast<uint8_t>(level));
      }
    }
  }
  const float* innermost = depth == 0 ? rings.ringPoints(r) : levels.data() + (depth - 1) * refinedFloats;
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
