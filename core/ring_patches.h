// The regular patches one FAS step uncovers (MATH.md §1): in each sector, the children
// [1,2]×[0,1], [1,2]² and [0,1]×[1,2] of the inner quad are uniform bicubic B-splines whose 4×4
// nets lie inside the refined (12n+1) point set. Nets that cross a sharp spoke or an open ring's
// boundary use phantom points reflected across it (2·p_edge − p_inner), which is how OpenSubdiv's
// boundary patches extrapolate.
#pragma once

#include "core/cer_layout.h"
#include "core/fas_rules.h"
#include "core/host_device.h"
#include "core/vec3.h"

namespace tessera {

inline constexpr int kPatchesPerSector = 3;

// Lattice origin (lower-left corner) of sector patch k at the refined level: A, B, C.
TESSERA_HD void sectorPatchOrigin(int k, int& x0, int& y0) {
  x0 = k == 2 ? 0 : 1;
  y0 = k == 0 ? 0 : 1;
}

// Fills the 16 B-spline control points of sector patch k (0: A, 1: B, 2: C) from a refined set
// of one ring (3 floats per point, relative coordinates as stored).
TESSERA_HD void sectorPatchNet(const RingRules& rules, const float* refined, int sector, int k,
                               Vec3 net[16]) {
  int x0, y0;
  sectorPatchOrigin(k, x0, y0);
  // Patch A's bottom edge lies on spoke `sector`; patch C's left edge on spoke `sector + 1`.
  bool phantomRow = k == 0 && rules.spokeSharp(sector);
  bool phantomColumn = k == 2 && rules.spokeSharp(rules.nextSector(sector));
  auto fetch = [&](int x, int y) {
    int index = cer::refinedIndex(rules.shape, sector, x, y);
    const float* p = refined + 3 * index;
    return Vec3(p[0], p[1], p[2]);
  };
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) {
      int x = x0 - 1 + col, y = y0 - 1 + row;
      if (phantomRow && row == 0) {
        net[4 * row + col] = fetch(x, 0) * 2.0f - fetch(x, 1);
      } else if (phantomColumn && col == 0) {
        net[4 * row + col] = fetch(0, y) * 2.0f - fetch(1, y);
      } else {
        net[4 * row + col] = fetch(x, y);
      }
    }
  }
}

}  // namespace tessera
