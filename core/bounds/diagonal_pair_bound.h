// The twist-free pair bound of docs/ADAPTIVE.md §3b, gathered piece by piece: each leaf (or a
// node standing for its leaves) against an ancestor's pair through its diagonal map.
#pragma once

#include <array>
#include <cmath>
#include <optional>

#include "core/bounds/diagonal_reparameterization.h"
#include "core/math/bezier_net.h"

namespace tessera {

// A leaf's own bounds, in an ancestor's units: its square [x, x + s] × [y, y + s], its corner
// values, its distance from their bilinear B (with its stand-in r) and its sides' from their chords.
struct LeafOwn {
  Vec3d corners[4];
  double x, y, s;
  double pair, bows[4];
  Vec3d bilinear(double u, double v) const { return bilinearAt(corners, (u - x) / s, (v - y) / s); }
};

// A square's Bézier net, computed from its parent's only when asked for (and not even zeroed
// before: most squares' cheap bounds settle them without it).
class LazyNet {
 public:
  explicit LazyNet(const BezierNet& net) : net_(net) {}
  LazyNet(const LazyNet* parent, int quadrant) : parent_(parent), quadrant_(quadrant) {}
  const BezierNet& get() const {
    if (!net_) net_.emplace(quadrantNet(parent_->get(), quadrant_ & 1, quadrant_ >> 1));
    return *net_;
  }

 private:
  const LazyNet* parent_ = nullptr;
  int quadrant_ = 0;
  mutable std::optional<BezierNet> net_;
};

// Raises `pair` and `bows` (the ancestor's maxima) to bound the square [x, x + s]² of the leaf
// `own` (within r of the surface; `net` its net, or null for a node standing for its leaves).
// Stops as soon as `pair` is above `abortAbove`: the maxima are then incomplete, and only the
// fact that the pair bound exceeds it is known.
void pieceAgainstDiagonal(const LazyNet* net, double r, const LeafOwn& own, double x, double y, double s,
                          const DiagonalMap& map, double& pair, std::array<double, 4>& bows,
                          double abortAbove = INFINITY);

}  // namespace tessera
