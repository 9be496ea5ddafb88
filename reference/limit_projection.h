// The point of the limit surface nearest to a point in space, as measured distances need it:
// Gauss-Newton minimisation of |f(u,v) - p|^2 inside one domain, the step projected onto
// [0,1]^2 (coordinates on the border whose gradient points outward are held) and halved until
// the distance decreases; and a kd-tree (nanoflann) of limit samples that proposes starting
// points in the domains near p, so that a projection can land in a neighbouring face.
#pragma once

#include <limits>
#include <memory>
#include <vector>

#include "reference/limit_surface.h"

namespace tessera::testing {

struct LimitPoint {
  int domain = -1;
  double u = 0, v = 0;
  Vec3d position;
  double distance = std::numeric_limits<double>::infinity();
};

// Local minimum of |f(u,v) - p| reached from (u, v) of `domain` (clamped to [0,1]^2). Stops when
// a step moves the surface point by less than `tolerance` (object units). A minimum held on a
// spoke of an n-gon's sub-face, with the gradient pointing across it, goes on in the neighbouring
// sub-face (LimitSurface::continueDomain); across a face's own edges the caller's other seeds
// must reach the neighbouring face.
LimitPoint projectInDomain(const LimitSurface& surface, const Vec3d& p, int domain, double u,
                           double v, double tolerance, int maxIterations = 40);

// One Gauss-Newton step from (u, v) and the nearer of the two points: two evaluations, an upper
// bound of the distance that is already tight when (u, v) is close to the foot point (a good
// parametric seed), which is what a first pass over millions of samples wants.
LimitPoint projectOneStep(const LimitSurface& surface, const Vec3d& p, int domain, double u,
                          double v);

class LimitSeedIndex {
 public:
  // samplesPerSide² limit samples per domain, at the centres of a uniform grid of cells.
  LimitSeedIndex(const LimitSurface& surface, int samplesPerSide);
  ~LimitSeedIndex();

  // Starting points near p: the nearest samples, at most one per domain (the nearest in it),
  // at most `count`, nearest first. Returns how many were written.
  int seeds(const Vec3d& p, int count, LimitPoint* out) const;
  // The sample of `domain` nearest to p (every sample of the domain compared).
  LimitPoint nearestIn(int domain, const Vec3d& p) const;

 private:
  struct Cloud;
  struct Tree;
  LimitPoint sampleAt(uint32_t index) const;

  int samplesPerSide_;
  std::unique_ptr<Cloud> cloud_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace tessera::testing
