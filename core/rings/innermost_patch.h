// The bicubic Bézier that stands in for the limit surface of an innermost quad after FAS
// (paper §5, MATH.md §2): ACC-1 (Loop & Schaefer 2008) inside and along smooth spokes, with the
// outer edges taken exactly from the neighbouring B-spline patches so the approximation is
// continuous with its regular neighbours for every ring kind, and sharp spokes following their
// crease curve. The EV corner is the exact limit position. The construction is linear in the
// ring, so the depth tables (depth_bound.h) bound its error exactly as shipped.
#pragma once

#include "core/base/host_device.h"
#include "core/math/bicubic.h"
#include "core/rings/cer_layout.h"
#include "core/rings/fas_rules.h"
#include "core/rings/ring_patches.h"

namespace tessera {

namespace innermost_detail {

// ACC-1 interior point at a corner c of valence k: (k c + 2 e_a + 2 e_b + d) / (k + 5).
template <typename P, typename S = typename ScalarOf<P>::type>
TESSERA_HD P accInterior(S k, const P& c, const P& ea, const P& eb, const P& d) {
  return (c * k + (ea + eb) * S(2) + d) * (S(1) / (k + S(5)));
}

}  // namespace innermost_detail

// Valence the ACC-1 EV formulas use for a sector. A smooth EV uses its valence n. Where sharp
// spokes (creases, boundaries) split the EV into wedges of f faces, each wedge behaves like a
// reflected copy: 2f faces for the crease rule, 4f for a corner, which makes the construction
// exact for the regular cases (a boundary vertex with two faces, a single-face corner, a
// straight crease through a valence-4 vertex).
TESSERA_HD int effectiveValence(const RingRules& rules, int sector) {
  const int n = rules.shape.sectors;
  if (rules.evRule == EvRule::kSmooth) return n;
  int faces = 1;
  for (int s = sector; !rules.spokeSharp(s) && faces <= n; s = rules.prevSector(s)) ++faces;
  for (int s = rules.nextSector(sector); !rules.spokeSharp(s) && faces <= n; s = rules.nextSector(s)) {
    ++faces;
  }
  return (rules.evRule == EvRule::kCrease ? 2 : 4) * faces;
}

// Limit position of the EV under its Sdc rule (smooth mask, crease mask, or corner).
template <typename P, typename Fetch>
TESSERA_HD P extraordinaryLimit(const RingRules& rules, Fetch ring) {
  using namespace cer;
  using S = typename ScalarOf<P>::type;
  const P ev = ring(0);
  if (rules.evRule == EvRule::kCorner) return ev;
  if (rules.evRule == EvRule::kCrease) {
    return ev * (S(2) / S(3)) +
           (ring(ringIndex(rules.creaseSpokeA, kE)) + ring(ringIndex(rules.creaseSpokeB, kE))) *
               (S(1) / S(6));
  }
  const int n = rules.shape.sectors;
  P sum = ring(ringIndex(0, kE)) * S(4) + ring(ringIndex(0, kD));
  for (int i = 1; i < n; ++i) sum = sum + ring(ringIndex(i, kE)) * S(4) + ring(ringIndex(i, kD));
  return (ev * S(n * n) + sum) * (S(1) / S(n * (n + 5)));
}

// Bézier control points (row-major, s along spoke `sector`, t along the next spoke) of the
// innermost quad of `sector`, from its ring. `ring(index)` returns the point at a CER index.
// `limit`, when given, is extraordinaryLimit of the same ring: a caller that takes every sector
// computes that O(n) sum once instead of once per sector.
template <typename P, typename Fetch>
TESSERA_HD void innermostBezier(const RingRules& rules, int sector, Fetch ring, P out[16], const P* limit = nullptr) {
  using namespace cer;
  using innermost_detail::accInterior;
  using S = typename ScalarOf<P>::type;
  const int i = sector, next = rules.nextSector(sector);
  const S k = S(effectiveValence(rules, sector));
  const P ev = ring(0), e = ring(ringIndex(i, kE)), d = ring(ringIndex(i, kD));
  const P eNext = ring(ringIndex(next, kE));

  // Outer edges: the boundary curves of the neighbouring B-spline patches A (x = 1) and C (y = 1).
  P column[4], row[4];
  for (int r = 0; r < 4; ++r) {
    auto net = [&](int c) { return sectorNetPoint<P>(rules, i, 0, r, c, ring); };
    column[r] = (net(0) + net(1) * S(4) + net(2)) * (S(1) / S(6));
  }
  for (int c = 0; c < 4; ++c) {
    auto net = [&](int r) { return sectorNetPoint<P>(rules, i, 2, r, c, ring); };
    row[c] = (net(0) + net(1) * S(4) + net(2)) * (S(1) / S(6));
  }
  P columnBezier[4], rowBezier[4];
  bsplineToBezierCurve(column, columnBezier);
  bsplineToBezierCurve(row, rowBezier);
  for (int r = 0; r < 4; ++r) out[4 * r + 3] = columnBezier[r];
  for (int c = 0; c < 3; ++c) out[12 + c] = rowBezier[c];

  // Interior: ACC-1 points of the four corners.
  const P bEv = accInterior(k, ev, e, eNext, d);
  out[5] = bEv;
  out[6] = accInterior(S(4), e, ev, d, eNext);
  out[10] = accInterior(S(4), d, e, eNext, ev);
  out[9] = accInterior(S(4), eNext, ev, d, e);

  // Spokes from the EV: a crease curve when sharp, else the average of the two sectors' ACC-1
  // points (summed in the same order from both sides).
  out[0] = limit ? *limit : extraordinaryLimit<P>(rules, ring);
  if (rules.spokeSharp(i)) {
    out[1] = (ev * S(2) + e) * (S(1) / S(3));
    out[2] = (ev + e * S(2)) * (S(1) / S(3));
  } else {
    int prev = rules.prevSector(i);
    const P ePrev = ring(ringIndex(prev, kE)), dPrev = ring(ringIndex(prev, kD));
    P bEvPrev = accInterior(k, ev, ePrev, e, dPrev);
    P bEPrev = accInterior(S(4), e, ev, dPrev, ePrev);
    out[1] = (bEvPrev + bEv) * S(0.5);
    out[2] = (bEPrev + out[6]) * S(0.5);
  }
  if (rules.spokeSharp(next)) {
    out[4] = (ev * S(2) + eNext) * (S(1) / S(3));
    out[8] = (ev + eNext * S(2)) * (S(1) / S(3));
  } else {
    int nextNext = rules.nextSector(next);
    const P eNextNext = ring(ringIndex(nextNext, kE)), dNext = ring(ringIndex(next, kD));
    P bEvNext = accInterior(k, ev, eNext, eNextNext, dNext);
    P bENext = accInterior(S(4), eNext, ev, dNext, eNextNext);
    out[4] = (bEv + bEvNext) * S(0.5);
    out[8] = (out[9] + bENext) * S(0.5);
  }
}

}  // namespace tessera
