// The regular patches one FAS step uncovers (MATH.md §1): in each sector, the children
// [1,2]×[0,1], [1,2]² and [0,1]×[1,2] of the inner quad are uniform bicubic B-splines whose 4×4
// nets lie inside the refined (12n+1) point set. Nets that cross a sharp spoke or an open ring's
// boundary use phantom points reflected across it (2·p_edge − p_inner), which is how OpenSubdiv's
// boundary patches extrapolate.
#pragma once

#include "core/base/host_device.h"
#include "core/base/vec3.h"
#include "core/rings/cer_layout.h"
#include "core/rings/fas_rules.h"

namespace tessera {

inline constexpr int kPatchesPerSector = 3;

// Lattice origin (lower-left corner) of sector patch k at the refined level: A, B, C.
TESSERA_HD void sectorPatchOrigin(int k, int& x0, int& y0) {
  x0 = k == 2 ? 0 : 1;
  y0 = k == 0 ? 0 : 1;
}

// Where control point (row, col) of sector patch k's 4×4 net comes from in a point set laid out
// like the refined set (the ring itself works for nets that stay within lattice coordinate 2):
// the point at `index`, or across a sharp spoke the phantom 2·p[index] − p[inner] (inner >= 0).
// The same at every FAS level of a ring, so a walk over the levels can find it once.
struct NetSource {
  int index = 0;
  int inner = -1;
};

TESSERA_HD NetSource sectorNetSource(const RingRules& rules, int sector, int k, int row, int col) {
  int x0, y0;
  sectorPatchOrigin(k, x0, y0);
  auto at = [&](int x, int y) { return cer::refinedIndex(rules.shape, sector, x, y); };
  int x = x0 - 1 + col, y = y0 - 1 + row;
  // Patch A's bottom edge lies on spoke `sector`; patch C's left edge on the next spoke.
  if (k == 0 && row == 0 && rules.spokeSharp(sector)) return {at(x, 0), at(x, 1)};
  if (k == 2 && col == 0 && rules.spokeSharp(rules.nextSector(sector))) return {at(0, y), at(1, y)};
  return {at(x, y), -1};
}

// The point a source names; `fetch(index)` returns the point at a CER index; P is any type with
// + and scalar *.
template <typename P, typename Fetch>
TESSERA_HD P fetchNetPoint(NetSource source, Fetch fetch) {
  if (source.inner < 0) return fetch(source.index);
  return fetch(source.index) * 2.0f + fetch(source.inner) * -1.0f;
}

// Control point (row, col) of sector patch k's net.
template <typename P, typename Fetch>
TESSERA_HD P sectorNetPoint(const RingRules& rules, int sector, int k, int row, int col, Fetch fetch) {
  return fetchNetPoint<P>(sectorNetSource(rules, sector, k, row, col), fetch);
}

// The 16 sources of sector patch k's net, row-major.
TESSERA_HD void sectorNetSources(const RingRules& rules, int sector, int k, NetSource out[16]) {
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) out[4 * row + col] = sectorNetSource(rules, sector, k, row, col);
  }
}

// A net gathered from a refined set (3 floats per point, relative coordinates as stored), with
// sectorNetPoint's arithmetic.
TESSERA_HD void gatherNet(const float* refined, const NetSource sources[16], Vec3 net[16]) {
  auto fetch = [refined](int index) {
    const float* p = refined + 3 * index;
    return Vec3(p[0], p[1], p[2]);
  };
  for (int q = 0; q < 16; ++q) net[q] = fetchNetPoint<Vec3>(sources[q], fetch);
}

}  // namespace tessera
