// Depth estimation at run time (paper §5.2): the smallest FAS depth m whose Tier-1 bound
// c_m · max_l ‖q_l − c‖ meets a ring's share ηε of the tolerance. Coefficients come from the
// tables checked in as core/bounds/depth_tables_data.inc (smooth interior and boundary rings) and
// core/bounds/depth_tables_creased.inc (sharp spokes or a corner EV: every pattern of valence
// 2..8 and of open rings of 1..6 faces, by canonical rotation), both written by
// tools/depth_tables/generate_depth_tables.cpp; are computed once per process for other ring
// kinds when that is cheap; and otherwise the depth is found by refining with an a-posteriori
// convex-hull bound.
#pragma once

#include <vector>

#include "core/rings/fas_rules.h"

namespace tessera {

struct DepthEstimate {
  int depth = 0;
  double bound = 0;  // guaranteed distance between the limit surface and the approximation
};

// The coefficients for a ring kind, or nullptr when none are available (fallback kinds).
const std::vector<double>* depthCoefficients(const RingRules& rules);

// `ring`: the ring's points relative to its EV (xyz floats), radius computed here in O(6n+1).
// `tolerance`: the ring's budget ηε. Depth is capped at kMaxTableDepth; `bound` says what was
// achieved (it exceeds the tolerance only when the cap was hit).
DepthEstimate estimateDepth(const RingRules& rules, const float* ring, double tolerance);

// max_l ‖q_l − c‖ of a ring stored relative to its EV c: the radius the coefficients multiply.
double ringRadius(const RingRules& rules, const float* ring);

// The guaranteed distance after a given depth (uniform mode).
double boundAtDepth(const RingRules& rules, const float* ring, int depth);

}  // namespace tessera
