#include "core/uniform/tessellation_plan.h"

#include <tbb/combinable.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/bounds/depth_bound.h"
#include "core/bounds/depth_tables.h"
#include "core/math/bezier_net.h"
#include "core/math/bicubic.h"
#include "core/rings/fas_rules.h"
#include "core/rings/innermost_patch.h"
#include "core/rings/ring_patches.h"
#include "core/rings/ring_refinement.h"
#include "core/surface/tolerance_model.h"
#include "core/uniform/uniform_levels.h"

namespace tessera {

namespace {

// M_uu + 2 M_uv + M_vv of a bicubic Bézier from its second differences (MATH.md §4).
double curvatureBound(const Vec3* b) {
  Vec3d net[16];
  for (int k = 0; k < 16; ++k) net[k] = Vec3d(b[k]);
  const Curvature m = netCurvature(net);
  return m.uu + 2 * m.uv + m.vv;
}

// What planning a piece needs besides the piece: the request and its tolerance model.
struct Planning {
  const TessellationOptions& options;
  const ToleranceModel& tolerance;
};

void assignLevel(BezierPiece& piece, const Planning& planning, double epsilon) {
  const TessellationOptions& options = planning.options;
  piece.tolerance = float(epsilon + piece.approximationBound);
  if (options.accuracy.uniform()) {
    piece.level = uniformPieceLevel(options.accuracy.level, piece.depth);
    piece.tessellationBound =
        float(curvatureBound(piece.bezier.data()) / (8.0 * piece.level * piece.level));
    return;
  }
  double achieved;
  piece.level = tessellationLevel(piece.bezier.data(), epsilon, achieved);
  piece.tessellationBound = float(achieved);
}

// Single phase (η = 0): an innermost piece is one triangle pair, within ε with its approximation
// bound by the choice of depth (singlePhaseDepth).
void assignTrianglePair(BezierPiece& piece, double epsilon) {
  piece.level = 1;
  piece.tessellationBound = float(curvatureBound(piece.bezier.data()) / 8);
  piece.tolerance = float(epsilon);
}

// Every field of a piece that is a B-spline patch exactly (a reused slot keeps nothing old).
void planExactPiece(BezierPiece& piece, const ControlNet& bspline, const PatchDomain& domain,
                    PieceKind kind, int depth, const Planning& planning) {
  bsplineToBezier(bspline.data(), piece.bezier.data());
  piece.domain = domain;
  piece.kind = kind;
  piece.depth = static_cast<uint8_t>(depth);
  piece.approximationBound = 0;
  piece.ring = -1;
  assignLevel(piece, planning, planning.tolerance.forPoints(piece.bezier.data(), 16));
}

// Sdc's smooth limit tangent masks (catmarkScheme.h): the exact normal at a smooth EV.
Vec3d smoothLimitNormal(const RingRules& rules, const float* ring) {
  const int n = rules.shape.sectors;
  const double theta = 2 * M_PI / n;
  const double lambda =
      5.0 / 16 +
      (std::cos(theta) + std::cos(theta / 2) * std::sqrt(2 * (9 + std::cos(theta)))) / 16;
  const double faceScale = n == 4 ? 1.0 : 1.0 / (4 * lambda - 1);
  auto point = [&](int index) {
    return Vec3d(ring[3 * index], ring[3 * index + 1], ring[3 * index + 2]);
  };
  Vec3d t1, t2;
  for (int i = 0; i < n; ++i) {
    double edge = 4 * std::cos(i * theta),
           face = faceScale * (std::cos(i * theta) + std::cos((i + 1) * theta));
    Vec3d e = point(cer::ringIndex(i, cer::kE)), d = point(cer::ringIndex(i, cer::kD));
    t1 += e * edge + d * face;
    int j = (i + 1) % n;  // tan2 is tan1 rotated by one position
    t2 += point(cer::ringIndex(j, cer::kE)) * edge + point(cer::ringIndex(j, cer::kD)) * face;
  }
  Vec3d normal = cross(t1, t2);
  double l = length(normal);
  return l > 0 ? normal * (1.0 / l) : Vec3d();
}

// What is known of a ring before it is refined: enough to give its pieces their slots.
struct RingLayout {
  int depth = 0;
  double bound = 0;  // of its innermost pieces
  size_t first = 0;  // its first piece in the plan
};

// η = 0, the paper's single-phase baseline: the innermost quads' limit surfaces are approximated
// directly by triangle pairs between their exact limit corners (the ACC-1 pieces at N = 1), so
// the depth is the smallest at which the ACC-1 bound plus FMM86 at N = 1 meets all of ε on every
// owned sector. Found by refining, since the FMM86 part depends on the refined ring.
DepthEstimate singlePhaseDepth(const RingSet& rings, size_t r, double epsilon) {
  const RingRules rules = rings.rules(r);
  const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
  const int ringFloats = 3 * rules.shape.ringPointCount();
  std::vector<float> ring(rings.ringPoints(r), rings.ringPoints(r) + ringFloats);
  std::vector<float> refined(3 * size_t(rules.shape.refinedPointCount()));
  for (int depth = 0;; ++depth) {
    const double approximation = boundAtDepth(rules, rings.ringPoints(r), depth);
    double flat = 0;
    forEachInnermostNet(rules, ring.data(), Vec3(), owned,
                        [&flat](int, const Vec3* net) { flat = std::max(flat, curvatureBound(net) / 8); });
    if (approximation + flat <= epsilon || depth == kMaxTableDepth) return {depth, approximation};
    refineRingStep<3>(rules, ring.data(), refined.data());
    std::copy(refined.begin(), refined.begin() + ringFloats, ring.begin());
  }
}

RingLayout layoutRing(const RingSet& rings, size_t r, const Planning& planning) {
  const TessellationOptions& options = planning.options;
  const RingRules rules = rings.rules(r);
  const float* ring = rings.ringPoints(r);
  RingLayout layout;
  if (options.accuracy.uniform()) {
    layout.depth = uniformRingDepth(options.accuracy.level, rings.levels[r]);
    layout.bound = boundAtDepth(rules, ring, layout.depth);
    return layout;
  }
  const double epsilon =
      planning.tolerance.forRing(ring, rules.shape.ringPointCount(), rings.centers[r]);
  DepthEstimate estimate = options.eta == 0 ? singlePhaseDepth(rings, r, epsilon)
                                            : estimateDepth(rules, ring, options.eta * epsilon);
  layout.depth = estimate.depth;
  layout.bound = estimate.bound;
  return layout;
}

// Gives every ring its range of slots after the regular pieces.
size_t placeRings(const RingSet& rings, size_t regularPieces, std::vector<RingLayout>& layouts) {
  size_t next = regularPieces;
  for (size_t r = 0; r < rings.size(); ++r) {
    layouts[r].first = next;
    next += size_t(ringPieceCount(rings, r, layouts[r].depth));
  }
  return next;
}

// The FAS patches of levels 1..depth, then the innermost Béziers, in the order emitRingPieces
// gives them, written from out[0]. `scratch` is the thread's room for the ring walk.
void planRingPieces(const RingSet& rings, size_t r, const RingLayout& layout,
                    const Planning& planning, RingWalkScratch& scratch, BezierPiece* out,
                    Vec3d& evNormal) {
  const RingRules rules = rings.rules(r);
  const cer::RingShape& shape = rules.shape;
  const Vec3 center = rings.centers[r];
  const PatchDomain* sectorDomains = rings.sectorDomains.data() + rings.sectorOffsets[r];
  const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
  const float* innermost = forEachRingPatch(
      rings, r, layout.depth, scratch, [&](const ControlNet& net, PatchDomain domain, int level) {
        planExactPiece(*out++, net, domain, PieceKind::kFas, rings.levels[r] + level, planning);
      });
  const double size = std::ldexp(1.0, -layout.depth);
  forEachInnermostNet(rules, innermost, center, owned, [&](int i, const Vec3* net) {
    BezierPiece& piece = *out++;
    std::copy(net, net + 16, piece.bezier.data());
    piece.domain = sectorDomains[i].restrict(0, 0, size);
    piece.kind = PieceKind::kInnermost;
    piece.depth = static_cast<uint8_t>(rings.levels[r] + layout.depth);
    piece.approximationBound = float(layout.bound);
    piece.ring = static_cast<int>(r);
    double pieceEpsilon = planning.tolerance.forPoints(piece.bezier.data(), 16);
    if (planning.options.eta == 0 && !planning.options.accuracy.uniform()) {
      assignTrianglePair(piece, pieceEpsilon);
      return;
    }
    double epsilon =
        std::max(pieceEpsilon - layout.bound, (1 - planning.options.eta) * pieceEpsilon);
    assignLevel(piece, planning, epsilon);
  });
  evNormal = Vec3d();
  if (rules.evRule != EvRule::kSmooth || shape.sectors == 2) return;
  for (int s = 0; s < shape.spokeCount(); ++s) {
    if (rules.spokeSharp(s)) return;
  }
  evNormal = smoothLimitNormal(rules, innermost);
}

// The plan's bound and smallest tolerance, gathered per thread while the pieces are planned.
struct PlanExtremes {
  double bound = 0, tolerance = INFINITY;

  void add(const BezierPiece* pieces, size_t count) {
    for (size_t p = 0; p < count; ++p) {
      bound = std::max(bound, double(pieces[p].approximationBound) + pieces[p].tessellationBound);
      tolerance = std::min(tolerance, double(pieces[p].tolerance));
    }
  }
  void merge(const PlanExtremes& other) {
    bound = std::max(bound, other.bound);
    tolerance = std::min(tolerance, other.tolerance);
  }
};

void planRegularPieces(const RegularPatches& regular, const Planning& planning,
                       TessellationPlan& plan, tbb::combinable<PlanExtremes>& extremes) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, regular.size(), 256), [&](const auto& range) {
    if (planning.options.checkpoint) planning.options.checkpoint();
    for (size_t p = range.begin(); p != range.end(); ++p) {
      planExactPiece(plan.pieces[p], regular.bspline[p], regular.domains[p], PieceKind::kRegular,
                     regular.levels[p], planning);
    }
    extremes.local().add(plan.pieces.data() + range.begin(), range.size());
  });
}

void planRings(const RingSet& rings, const std::vector<RingLayout>& layouts,
               const Planning& planning, TessellationPlan& plan,
               tbb::combinable<PlanExtremes>& extremes) {
  tbb::enumerable_thread_specific<RingWalkScratch> scratch;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rings.size(), 8), [&](const auto& range) {
    RingWalkScratch& walk = scratch.local();
    for (size_t r = range.begin(); r != range.end(); ++r) {
      if (planning.options.checkpoint && r % 64 == 0) planning.options.checkpoint();
      BezierPiece* first = plan.pieces.data() + layouts[r].first;
      planRingPieces(rings, r, layouts[r], planning, walk, first, plan.evNormals[r]);
      const size_t end = r + 1 < rings.size() ? layouts[r + 1].first : plan.pieces.size();
      extremes.local().add(first, end - layouts[r].first);
    }
  });
}

}  // namespace

int tessellationLevel(const Vec3* b, double epsilon, double& achievedBound) {
  const double curvature = curvatureBound(b);
  int level = 1;
  if (std::isfinite(epsilon) && curvature > 0) {
    level = int(std::clamp(std::ceil(std::sqrt(curvature / (8 * epsilon))), 1.0, 1e6));
  }
  achievedBound = curvature / (8.0 * level * level);
  return level;
}

TessellationPlan planTessellation(const PatchSet& patches, const TessellationOptions& options) {
  TessellationPlan plan;
  planTessellation(patches, options, plan);
  return plan;
}

void planTessellation(const PatchSet& patches, const TessellationOptions& options,
                      TessellationPlan& plan) {
  validateTessellationOptions(options);
  const ToleranceModel tolerance(options, patches);
  const Planning planning{options, tolerance};
  const RingSet& rings = patches.rings;
  std::vector<RingLayout> layouts(rings.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rings.size(), 16), [&](const auto& range) {
    for (size_t r = range.begin(); r != range.end(); ++r)
      layouts[r] = layoutRing(rings, r, planning);
  });
  plan.pieces.resize(
      placeRings(rings, patches.regular.size(), layouts));  // same size: nothing touched
  plan.evNormals.resize(rings.size());
  tbb::combinable<PlanExtremes> extremes;
  planRegularPieces(patches.regular, planning, plan, extremes);
  planRings(rings, layouts, planning, plan, extremes);

  long depthSum = 0;
  plan.maxDepth = 0;
  for (const RingLayout& layout : layouts) {
    depthSum += layout.depth;
    plan.maxDepth = std::max(plan.maxDepth, layout.depth);
  }
  plan.rings = static_cast<int>(rings.size());
  plan.averageDepth = plan.rings ? double(depthSum) / plan.rings : 0.0;
  PlanExtremes all;
  extremes.combine_each([&](const PlanExtremes& e) { all.merge(e); });
  plan.guaranteedBound = all.bound;
  plan.tolerance = plan.pieces.empty() ? tolerance.forPoints(nullptr, 0) : all.tolerance;
}

}  // namespace tessera
