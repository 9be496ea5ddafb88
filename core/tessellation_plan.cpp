#include "core/tessellation_plan.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "core/bicubic.h"
#include "core/depth_tables.h"
#include "core/error.h"
#include "core/fas.h"
#include "core/innermost_patch.h"
#include "core/ring_refinement.h"

namespace tessera {

namespace {

// Object-space tolerance for a piece of geometry: ε itself, or ε from the camera (MATH.md §4):
// ε_obj = px · z / (f_px · √(1 + tan²(φx/2) + tan²(φy/2))) at the piece's nearest depth z
// (convex hull of its control points), z reduced by ε_obj itself, clamped at a near plane.
class ToleranceModel {
 public:
  ToleranceModel(const TessellationOptions& options, const PatchSet& patches) : options_(options) {
    double diagonal = length(Vec3d(patches.boundsMax) - Vec3d(patches.boundsMin));
    epsilon_ = options.relativeTolerance ? options.tolerance * diagonal : options.tolerance;
    if (!options.camera) return;
    const Camera& c = *options.camera;
    forward_ = c.target - c.eye;
    forward_ = forward_ * (1.0 / length(forward_));
    double tanY = std::tan(c.fovYDegrees * M_PI / 360.0);
    double tanX = tanY * c.width / c.height;
    double focal = c.height / (2.0 * tanY);
    pixelScale_ = options.pixelAccuracy / (focal * std::sqrt(1 + tanX * tanX + tanY * tanY));
    near_ = 1e-2 * length(c.target - c.eye);
  }

  double forPoints(const Vec3* points, int count, Vec3 offset = {}) const {
    if (!options_.camera) return epsilon_;
    double nearest = INFINITY;
    for (int i = 0; i < count; ++i) {
      nearest = std::min(nearest, dot(Vec3d(points[i] + offset) - options_.camera->eye, forward_));
    }
    double k = pixelScale_;
    return k * std::max(nearest, near_) / (1.0 + k);
  }

 private:
  const TessellationOptions& options_;
  double epsilon_ = 0;
  Vec3d forward_;
  double pixelScale_ = 0, near_ = 0;
};

int uniformLevel(int p, int depth) { return std::max(p >> std::min(depth, 30), 1); }

BezierPiece exactPiece(const ControlNet& bspline, const PatchDomain& domain, PieceKind kind, int depth) {
  BezierPiece piece;
  bsplineToBezier(bspline.data(), piece.bezier.data());
  piece.domain = domain;
  piece.kind = kind;
  piece.depth = static_cast<uint8_t>(depth);
  return piece;
}

// M_uu + 2 M_uv + M_vv of a bicubic Bézier from its second differences (MATH.md §4).
double curvatureBound(const Vec3* b) {
  auto at = [b](int row, int col) { return Vec3d(b[4 * row + col]); };
  double uu = 0, vv = 0, uv = 0;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 2; ++j) {
      uu = std::max(uu, length(at(i, j) - at(i, j + 1) * 2.0 + at(i, j + 2)));
      vv = std::max(vv, length(at(j, i) - at(j + 1, i) * 2.0 + at(j + 2, i)));
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) uv = std::max(uv, length(at(i, j) - at(i, j + 1) - at(i + 1, j) + at(i + 1, j + 1)));
  }
  return 6 * uu + 2 * 9 * uv + 6 * vv;
}

void assignLevel(BezierPiece& piece, const TessellationOptions& options, double epsilon) {
  piece.tolerance = float(epsilon + piece.approximationBound);
  if (options.uniformLevel > 0) {
    piece.level = uniformLevel(options.uniformLevel, piece.depth);
    piece.tessellationBound = float(curvatureBound(piece.bezier.data()) / (8.0 * piece.level * piece.level));
    return;
  }
  double achieved;
  piece.level = tessellationLevel(piece.bezier.data(), epsilon, achieved);
  piece.tessellationBound = float(achieved);
}

// Sdc's smooth limit tangent masks (catmarkScheme.h): the exact normal at a smooth EV.
Vec3d smoothLimitNormal(const RingRules& rules, const float* ring) {
  const int n = rules.shape.sectors;
  const double theta = 2 * M_PI / n;
  const double lambda = 5.0 / 16 + (std::cos(theta) + std::cos(theta / 2) * std::sqrt(2 * (9 + std::cos(theta)))) / 16;
  const double faceScale = n == 4 ? 1.0 : 1.0 / (4 * lambda - 1);
  auto point = [&](int index) { return Vec3d(ring[3 * index], ring[3 * index + 1], ring[3 * index + 2]); };
  Vec3d t1, t2;
  for (int i = 0; i < n; ++i) {
    double edge = 4 * std::cos(i * theta), face = faceScale * (std::cos(i * theta) + std::cos((i + 1) * theta));
    Vec3d e = point(cer::ringIndex(i, cer::kE)), d = point(cer::ringIndex(i, cer::kD));
    t1 += e * edge + d * face;
    int j = (i + 1) % n;  // tan2 is tan1 rotated by one position
    t2 += point(cer::ringIndex(j, cer::kE)) * edge + point(cer::ringIndex(j, cer::kD)) * face;
  }
  Vec3d normal = cross(t1, t2);
  double l = length(normal);
  return l > 0 ? normal * (1.0 / l) : Vec3d();
}

struct RingPlan {
  std::vector<BezierPiece> pieces;
  int depth = 0;
  Vec3d evNormal;
};

RingPlan planRing(const PatchSet& patches, size_t r, const TessellationOptions& options,
                  const ToleranceModel& tolerance) {
  const RingSet& rings = patches.rings;
  const RingRules rules = rings.rules(r);
  const Vec3 center = rings.centers[r];
  const float* ring = rings.ringPoints(r);
  std::vector<Vec3> ringPoints(rules.shape.ringPointCount());
  for (size_t p = 0; p < ringPoints.size(); ++p) ringPoints[p] = Vec3(ring[3 * p], ring[3 * p + 1], ring[3 * p + 2]);
  const double epsilon = tolerance.forPoints(ringPoints.data(), int(ringPoints.size()), center);

  RingPlan plan;
  DepthEstimate estimate{0, 0};
  if (options.uniformLevel > 0) {
    int target = int(std::ceil(std::log2(double(options.uniformLevel))));
    estimate.depth = std::max(0, target - rings.levels[r]);
    estimate.bound = boundAtDepth(rules, ring, estimate.depth);
  } else {
    estimate = estimateDepth(rules, ring, options.eta * epsilon);
  }
  plan.depth = estimate.depth;
  RingPieces pieces;
  emitRingPieces(rings, r, estimate.depth, pieces);
  for (size_t p = 0; p < pieces.bspline.size(); ++p) {
    BezierPiece piece = exactPiece(pieces.bspline[p], pieces.domains[p], PieceKind::kFas,
                                   rings.levels[r] + pieces.depths[p]);
    assignLevel(piece, options, tolerance.forPoints(piece.bezier.data(), 16));
    plan.pieces.push_back(piece);
  }
  const float* innermost = pieces.innermostRing.data();
  auto fetch = [innermost](int index) {
    return Vec3(innermost[3 * index], innermost[3 * index + 1], innermost[3 * index + 2]);
  };
  for (size_t k = 0; k < pieces.innermostSectors.size(); ++k) {
    BezierPiece piece;
    innermostBezier<Vec3>(rules, pieces.innermostSectors[k], fetch, piece.bezier.data());
    for (Vec3& b : piece.bezier) b += center;
    piece.domain = pieces.innermostDomains[k];
    piece.kind = PieceKind::kInnermost;
    piece.depth = static_cast<uint8_t>(rings.levels[r] + estimate.depth);
    piece.approximationBound = float(estimate.bound);
    piece.ring = static_cast<int>(r);
    double pieceEpsilon = tolerance.forPoints(piece.bezier.data(), 16);
    assignLevel(piece, options, std::max(pieceEpsilon - estimate.bound, (1 - options.eta) * pieceEpsilon));
    plan.pieces.push_back(piece);
  }
  if (rules.evRule == EvRule::kSmooth && rules.shape.sectors != 2) {
    for (int s = 0; s < rules.shape.spokeCount(); ++s) {
      if (rules.spokeSharp(s)) return plan;
    }
    plan.evNormal = smoothLimitNormal(rules, innermost);
  }
  return plan;
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
  validateTessellationOptions(options);
  ToleranceModel tolerance(options, patches);
  TessellationPlan plan;
  plan.pieces.resize(patches.regular.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, patches.regular.size(), 256), [&](const auto& range) {
    if (options.checkpoint) options.checkpoint();
    for (size_t p = range.begin(); p != range.end(); ++p) {
      BezierPiece& piece = plan.pieces[p];
      piece = exactPiece(patches.regular.bspline[p], patches.regular.domains[p], PieceKind::kRegular,
                         patches.regular.levels[p]);
      assignLevel(piece, options, tolerance.forPoints(piece.bezier.data(), 16));
    }
  });
  std::vector<RingPlan> ringPlans(patches.rings.size());
  tbb::parallel_for(size_t(0), patches.rings.size(), [&](size_t r) {
    if (options.checkpoint && r % 64 == 0) options.checkpoint();
    ringPlans[r] = planRing(patches, r, options, tolerance);
  });
  long depthSum = 0;
  for (RingPlan& ring : ringPlans) {
    plan.pieces.insert(plan.pieces.end(), ring.pieces.begin(), ring.pieces.end());
    plan.evNormals.push_back(ring.evNormal);
    depthSum += ring.depth;
    plan.maxDepth = std::max(plan.maxDepth, ring.depth);
  }
  plan.rings = static_cast<int>(ringPlans.size());
  plan.averageDepth = plan.rings ? double(depthSum) / plan.rings : 0.0;
  plan.tolerance = plan.pieces.empty() ? tolerance.forPoints(nullptr, 0) : INFINITY;
  for (const BezierPiece& piece : plan.pieces) {
    plan.guaranteedBound = std::max(plan.guaranteedBound, double(piece.approximationBound) + piece.tessellationBound);
    plan.tolerance = std::min(plan.tolerance, double(piece.tolerance));
  }
  return plan;
}

}  // namespace tessera
