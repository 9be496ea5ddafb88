#include "core/bounds/flat_pair_bound.h"

#include <algorithm>
#include <cmath>

namespace tessera {

namespace {

template <class P>
double cross2(P a, P b) {
  return a.x * b.y - a.y * b.x;
}

template <class P>
P minus(P a, P b) {
  return {a.x - b.x, a.y - b.y};
}

template <class P>
double segmentDistance(P p, P a, P b) {
  const P ab = minus(b, a), ap = minus(p, a);
  const double squared = ab.x * ab.x + ab.y * ab.y;
  const double t = squared > 0 ? std::clamp((ap.x * ab.x + ap.y * ab.y) / squared, 0.0, 1.0) : 0.0;
  return std::hypot(ap.x - t * ab.x, ap.y - t * ab.y);
}

}  // namespace

FlatGather::FlatGather(const Vec3d corners[4]) : low_(INFINITY), high_(-INFINITY) {
  const Vec3d normal = cross(corners[2] - corners[0], corners[3] - corners[1]);
  if (!(length(normal) > 0)) return;
  n_ = normal * (1 / length(normal));
  const Vec3d axis = std::abs(n_.x) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
  e1_ = axis - n_ * dot(axis, n_);
  e1_ = e1_ * (1 / length(e1_));
  e2_ = cross(n_, e1_);
  for (int k = 0; k < 4; ++k) quad_[k] = project(corners[k]);
  orientation_ = cross2(minus(quad_[1], quad_[0]), minus(quad_[2], quad_[1]));
  valid_ = true;
  for (int k = 0; k < 4; ++k) {
    const Point2 a = minus(quad_[(k + 1) % 4], quad_[k]),
                 b = minus(quad_[(k + 2) % 4], quad_[(k + 1) % 4]);
    valid_ = valid_ && cross2(a, b) * orientation_ > 0;
  }
}

// Distance to the convex quad: 0 inside (most of a piece's points), else to its nearest side.
double FlatGather::quadDistance(Point2 p) const {
  bool inside = true;
  for (int k = 0; k < 4 && inside; ++k) {
    inside = cross2(minus(quad_[(k + 1) % 4], quad_[k]), minus(p, quad_[k])) * orientation_ >= 0;
  }
  if (inside) return 0.0;
  double nearest = INFINITY;
  for (int k = 0; k < 4; ++k) nearest = std::min(nearest, segmentDistance(p, quad_[k], quad_[(k + 1) % 4]));
  return nearest;
}

// The distance to a convex set is convex, so the hull's points bound it over the surface.
void FlatGather::addPoint(const Vec3d& p, double radius) {
  const double h = dot(p, n_);
  low_ = std::min(low_, h - radius), high_ = std::max(high_, h + radius);
  outside_ = std::max(outside_, quadDistance(project(p)) + radius);
}

void FlatGather::addSidePoint(int side, const Vec3d& p, double radius) {
  reach_ =
      std::max(reach_, segmentDistance(project(p), quad_[side], quad_[(side + 1) % 4]) + radius);
}

// §3d: the piece's projection covers every point of the quad Q farther than G (reach) from Q's
// boundary (winding numbers), and each point of Q nearer the boundary lies within 2G of a side
// curve's projection; D (outside) bounds the surface's side; H (high − low) every height gap.
FlatPairBound FlatGather::bound() const {
  const double height = high_ - low_;
  return {std::hypot(height, std::max(outside_, 2 * reach_)),
          std::hypot(height, outside_ + 2 * reach_)};
}

void FlatGather::addNet(const BezierNet& net, double radius, uint8_t sides) {
  for (const Vec3d& p : net) addPoint(p, radius);
  for (int k = 0; k < 4; ++k) {
    if (!(sides >> k & 1)) continue;
    for (int index : kSideIndex[k]) addSidePoint(k, net[index], radius);
  }
}

std::optional<FlatPairBound> flatPairBound(const BezierNet& net) {
  const Vec3d corners[4] = {net[kCornerIndex[0]], net[kCornerIndex[1]], net[kCornerIndex[2]],
                            net[kCornerIndex[3]]};
  FlatGather gather(corners);
  if (!gather.valid()) return std::nullopt;
  gather.addNet(net, 0, 0xF);
  return gather.bound();
}

// Points on a side move a pair split along a kept diagonal by at most the side's bow along any
// monotone map of the side (§3), so the current bows hold beside the flat pair where a diagonal is
// kept; without one, only what any triangulation adds does.
bool keepFlatBound(const FlatPairBound& flat, const Vec3d corners[4], PairBounds& bounds) {
  if (!(flat.pair * (1 + 1e-9) < bounds.pair)) return false;
  const double anyTriangulation = flat.anyTriangulation * (1 + 1e-9);
  const double added = anyTriangulation - flat.pair;
  if (bounds.diagonal == 0 &&
      anyTriangulation > bounds.pair + *std::min_element(bounds.bows.begin(), bounds.bows.end())) {
    const Vec3d first = corners[2] - corners[0], second = corners[3] - corners[1];
    bounds.diagonal = dot(second, second) < dot(first, first) ? 2 : 1;
  }
  for (double& bow : bounds.bows) bow = bounds.diagonal == 0 ? added : std::min(bow, added);
  bounds.pair = flat.pair * (1 + 1e-9);
  return true;
}

}  // namespace tessera
