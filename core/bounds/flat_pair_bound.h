// The pair bound of a nearly flat square of the surface (docs/ADAPTIVE.md §3d): a geometric bound
// by projection onto one plane, which needs no map between the surface's parameters and the
// pair's. Pieces beside semi-sharp creases are slivers whose parameterization no map of §3b or
// §3c follows, while the surface lies within a small fraction of ε of one plane.
#pragma once

#include <cstdint>
#include <optional>

#include "core/bounds/graded_pair_bound.h"
#include "core/math/bezier_net.h"

namespace tessera {

struct FlatPairBound {
  // Two-sided distance between the square's surface and the pair through its corners (either
  // diagonal).
  double pair = 0;
  // The same for any triangulation whose vertices are the corners and points of the sides.
  double anyTriangulation = 0;
};

// What §3d gathers, projected along the normal n of the pair's diagonals: the surface's extent
// along n, its reach outside the projected corner quad, and its sides' reach from their chords,
// from points whose hull (grown by a radius) holds the surface or a side's curve.
class FlatGather {
 public:
  explicit FlatGather(const Vec3d corners[4]);
  // The corners project to a strictly convex quad (§3d's claim needs it).
  bool valid() const { return valid_; }
  // The surface lies in the hull of such points, each grown by its radius.
  void addPoint(const Vec3d& p, double radius);
  // Side k's curve lies in the hull of such points, each grown by its radius.
  void addSidePoint(int side, const Vec3d& p, double radius);
  // A bicubic piece within `radius` of the surface it stands for: its net for the surface, and
  // for each side in `sides` (bit k: the piece's side k lies on side k) that side's four points.
  void addNet(const BezierNet& net, double radius, uint8_t sides);
  FlatPairBound bound() const;

 private:
  struct Point2 {
    double x = 0, y = 0;
  };
  Point2 project(const Vec3d& p) const { return {dot(p, e1_), dot(p, e2_)}; }
  double quadDistance(Point2 p) const;

  Vec3d n_, e1_, e2_;
  Point2 quad_[4];
  double orientation_ = 0;
  bool valid_ = false;
  double low_, high_, outside_ = 0, reach_ = 0;
};

// §3d for one bicubic piece: every net point for the surface, each side's four for its curve.
std::optional<FlatPairBound> flatPairBound(const BezierNet& net);

// Takes the flat bound where its pair is below `bounds.pair`, with the bows and diagonal
// (SurfaceNode::pairDiagonal) that then hold; false where it keeps `bounds`.
bool keepFlatBound(const FlatPairBound& flat, const Vec3d corners[4], PairBounds& bounds);

}  // namespace tessera
