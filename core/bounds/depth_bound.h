// Tier-1 depth bound (paper Eq. 4, MATH.md §3): coefficients c_m such that, after m FAS steps,
// the distance between the true limit surface of the innermost quads and their Bézier
// approximation (innermost_patch.h) is at most c_m · max_l ‖q_l − c‖₂ over the ring's points q_l
// and any centre c. Computed in double precision from the exact linear model of the ring: the
// ring step A, the refinement S, the patch nets, the construction, on dyadic tiles plus a
// convex-hull tail.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/rings/cer_layout.h"
#include "core/rings/fas_rules.h"

namespace tessera {

struct RingKind {
  cer::RingShape shape;
  std::vector<uint8_t> sharpSpokes;  // spokeCount() flags (empty: all smooth)
  bool cornerEv = false;
};

inline constexpr int kMaxTableDepth = 24;
inline constexpr int kBoundTiles = 14;

// The kind a ring's rules make: a flag per spoke (an open ring's boundary spokes sharp), and
// cornerEv exactly where the EV takes the corner rule.
RingKind ringKindOf(const RingRules& rules);
// The kind with its spokes rotated to the smallest pattern (a closed ring; an open one as it is):
// kinds one rotation apart are one ring with its sectors numbered from another, so one bound.
RingKind canonicalRotation(const RingKind& kind);
// A kind's name in the tables: its faces, "c" or "o" (closed, open), "x" or "-" (corner EV or
// not), then 1 or 0 per spoke (sharp or not); "5c-10100": a crease through an EV of valence 5.
std::string ringKindKey(const RingKind& kind);

// c_0 .. c_maxDepth for a ring kind.
std::vector<double> computeDepthBound(const RingKind& kind, int maxDepth = kMaxTableDepth,
                                      int tiles = kBoundTiles);

// An approximation of sector `sector`'s innermost quad: its 16 Bézier control points (row-major,
// s along spoke `sector`) as a linear function of the ring's points.
using SectorApproximation = std::function<void(int sector, const double* ring, double out[16])>;

// The same bound for any approximation (computeDepthBound's is innermostBezier; the benchmarks
// compare the control polyhedron's): c_m over every sector, or over sector 0 alone when the ring
// looks the same from each (`oneSector`).
std::vector<double> approximationBound(const RingRules& rules, bool oneSector, const SectorApproximation& approximate,
                                       int maxDepth = kMaxTableDepth, int tiles = kBoundTiles);

}  // namespace tessera
