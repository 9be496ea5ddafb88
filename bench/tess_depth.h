// The control-mesh comparator of the paper's Fig. 6 (§5.2): a depth bound for approximating the
// limit surface of a ring's innermost quads by the control polyhedron itself (the bilinear quads
// of the level-m control points), as the [HW07b]/[HDW08]/[PW09] family does, instead of by
// Tessera's ACC-1 Bézier patches (core/rings/innermost_patch.h).
//
// It is computed exactly the way core/bounds/depth_bound.cpp computes Tessera's Tier-1 tables
// (MATH.md §3), so that the two differ only in the approximation they bound: from the linear
// model of the ring (CC step from core/rings/fas_rules.h in double), the Bézier coefficients of
// (limit − bilinear quad) on 14 dyadic L-tiles per sector plus a convex-hull tail near the EV,
// giving dist(x, P_m) ≤ k_m · max_l ‖q_l − q_0‖ over the base ring's points. It is a proven
// parametric bound (the limit and the quad are compared at equal parameters), in the ring-radius
// form of the paper's Eq. (4) rather than with second differences: MATH.md §3 explains why a
// parametric bound cannot be written with second differences alone (a bilinear quad does not
// reproduce the limit of linear data near an EV). Like Tier 1 it decays like the subdominant
// eigenvalue λ per level.
//
// Also: the plain convex-hull bound 2·‖A^m − 1ℓᵀ‖∞ (both the limit and the quad lie in the hull
// of the level-m ring, every point of which is within ‖A^m − 1ℓᵀ‖∞·R of the limit point): the
// crudest a-priori bound of this form.
#pragma once

#include <vector>

#include "core/rings/fas_rules.h"

namespace tessera::bench {

struct ControlMeshBounds {
  std::vector<double> polyhedron;  // k_0 .. k_24: limit vs bilinear control quads, dyadic tiles
  std::vector<double> hull;        // h_0 .. h_24: 2‖A^m − 1ℓᵀ‖∞
};

// Computed once per ring kind (shape, sharp spokes, corner EV) and cached; thread-safe.
const ControlMeshBounds& controlMeshBounds(const RingRules& rules);

// The smallest m ≤ 24 with table[m] · radius ≤ tolerance (24 if none).
int depthFromTable(const std::vector<double>& table, double radius, double tolerance);

}  // namespace tessera::bench
