#include "core/flat_pair_bound.h"

#include <algorithm>
#include <cmath>

namespace tessera {

namespace {

struct Point2 {
  double x = 0, y = 0;
};

Point2 operator-(Point2 a, Point2 b) { return {a.x - b.x, a.y - b.y}; }
double cross2(Point2 a, Point2 b) { return a.x * b.y - a.y * b.x; }

double segmentDistance(Point2 p, Point2 a, Point2 b) {
  const Point2 ab = b - a, ap = p - a;
  const double squared = ab.x * ab.x + ab.y * ab.y;
  const double t = squared > 0 ? std::clamp((ap.x * ab.x + ap.y * ab.y) / squared, 0.0, 1.0) : 0.0;
  return std::hypot(ap.x - t * ab.x, ap.y - t * ab.y);
}

// The plane orthogonal to n: coordinates of a point's projection, and its height along n.
struct Projection {
  Vec3d n, e1, e2;

  explicit Projection(const Vec3d& normal) : n(normal * (1 / length(normal))) {
    const Vec3d axis = std::abs(n.x) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
    e1 = axis - n * dot(axis, n);
    e1 = e1 * (1 / length(e1));
    e2 = cross(n, e1);
  }
  Point2 operator()(const Vec3d& p) const { return {dot(p, e1), dot(p, e2)}; }
};

// Distance from p to the convex quad q (counter-clockwise when orientation > 0): 0 inside.
double quadDistance(Point2 p, const Point2 q[4], double orientation) {
  bool inside = true;
  double nearest = INFINITY;
  for (int k = 0; k < 4; ++k) {
    inside = inside && cross2(q[(k + 1) % 4] - q[k], p - q[k]) * orientation >= 0;
    nearest = std::min(nearest, segmentDistance(p, q[k], q[(k + 1) % 4]));
  }
  return inside ? 0.0 : nearest;
}

}  // namespace

// §3d: H, the net's extent along n, bounds every height difference (the pair's and any
// triangulation's vertices lie on the surface, inside the net's hull); D, the net's reach outside
// the projected quad Q (the distance to a convex set is convex, so the control points bound it);
// G, each side curve's reach from its chord (the same argument per side). The piece's projection
// covers every point of Q farther than G from Q's boundary (winding numbers), and each point of Q
// nearer the boundary lies within 2G of a side curve's projection.
std::optional<FlatPairBound> flatPairBound(const BezierNet& net) {
  const Vec3d c[4] = {net[kCornerIndex[0]], net[kCornerIndex[1]], net[kCornerIndex[2]], net[kCornerIndex[3]]};
  const Vec3d normal = cross(c[2] - c[0], c[3] - c[1]);
  if (!(length(normal) > 0)) return std::nullopt;
  const Projection project(normal);
  Point2 q[4];
  for (int k = 0; k < 4; ++k) q[k] = project(c[k]);
  const double orientation = cross2(q[1] - q[0], q[2] - q[1]);
  for (int k = 0; k < 4; ++k) {
    if (!(cross2(q[(k + 1) % 4] - q[k], q[(k + 2) % 4] - q[(k + 1) % 4]) * orientation > 0)) return std::nullopt;
  }
  double low = INFINITY, high = -INFINITY, outside = 0;
  for (const Vec3d& p : net) {
    const double h = dot(p, project.n);
    low = std::min(low, h), high = std::max(high, h);
    outside = std::max(outside, quadDistance(project(p), q, orientation));
  }
  static constexpr int kSide[4][4] = {{0, 1, 2, 3}, {3, 7, 11, 15}, {15, 14, 13, 12}, {12, 8, 4, 0}};
  double reach = 0;
  for (const auto& side : kSide) {
    const Point2 from = project(net[side[0]]), to = project(net[side[3]]);
    for (int j = 1; j < 3; ++j) reach = std::max(reach, segmentDistance(project(net[side[j]]), from, to));
  }
  const double height = high - low;
  return FlatPairBound{std::hypot(height, std::max(outside, 2 * reach)), std::hypot(height, outside + 2 * reach)};
}

// Points on a side move a pair split along a kept diagonal by at most the side's bow along any
// monotone map of the side (§3), so the current bows hold beside the flat pair where a diagonal is
// kept; without one, only what any triangulation adds does.
bool keepFlatBound(const BezierNet& net, PairBounds& bounds) {
  const std::optional<FlatPairBound> flat = flatPairBound(net);
  if (!flat || !(flat->pair * (1 + 1e-9) < bounds.pair)) return false;
  const double anyTriangulation = flat->anyTriangulation * (1 + 1e-9);
  const double added = anyTriangulation - flat->pair;
  if (bounds.diagonal == 0 && anyTriangulation > bounds.pair + *std::min_element(bounds.bows.begin(), bounds.bows.end())) {
    const Vec3d first = net[kCornerIndex[2]] - net[kCornerIndex[0]], second = net[kCornerIndex[3]] - net[kCornerIndex[1]];
    bounds.diagonal = dot(second, second) < dot(first, first) ? 2 : 1;
  }
  for (double& bow : bounds.bows) bow = bounds.diagonal == 0 ? added : std::min(bow, added);
  bounds.pair = flat->pair * (1 + 1e-9);
  return true;
}

}  // namespace tessera
