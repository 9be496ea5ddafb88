#include "core/surface/tolerance_model.h"

#include <algorithm>
#include <cmath>

namespace tessera {

ToleranceModel::ToleranceModel(const TessellationOptions& options, Vec3 boundsMin, Vec3 boundsMax) {
  const double diagonal = length(Vec3d(boundsMax) - Vec3d(boundsMin));
  // A uniform level meets no ε: the reserve only adds to its bound (tessellate.cpp).
  const Accuracy& accuracy = options.accuracy;
  reserve_ = accuracy.uniform() ? 0.0 : options.encodingReserve;
  // A level asks for no ε (0): the pieces' tolerances are then their approximation bounds alone.
  epsilon_ = accuracy.epsilonFor(diagonal) - reserve_;
  if (!accuracy.pixelAccurate()) return;
  const Camera& c = *options.camera;
  eye_ = c.eye;
  forward_ = c.target - c.eye;
  forward_ = forward_ * (1.0 / length(forward_));
  const double tanY = std::tan(c.fovYDegrees * M_PI / 360.0);
  const double tanX = tanY * c.width / c.height;
  const double focal = c.height / (2.0 * tanY);
  pixelScale_ = accuracy.pixels / (focal * std::sqrt(1 + tanX * tanX + tanY * tanY));
  near_ = 1e-2 * length(c.target - c.eye);
}

double ToleranceModel::atDepth(double nearest) const {
  const double k = pixelScale_;
  return k * std::max(nearest, near_) / (1.0 + k) - reserve_;
}

double ToleranceModel::forPoints(const Vec3* points, int count) const {
  if (!pixelAccurate()) return epsilon_;
  double nearest = INFINITY;
  for (int i = 0; i < count; ++i) nearest = std::min(nearest, depthOf(Vec3d(points[i])));
  return atDepth(nearest);
}

double ToleranceModel::forRing(const float* ring, int count, Vec3 center) const {
  if (!pixelAccurate()) return epsilon_;
  double nearest = INFINITY;
  for (int i = 0; i < count; ++i) {
    const Vec3 p = Vec3(ring[3 * i], ring[3 * i + 1], ring[3 * i + 2]) + center;
    nearest = std::min(nearest, depthOf(Vec3d(p)));
  }
  return atDepth(nearest);
}

double ToleranceModel::forBox(const float lo[3], const float hi[3]) const {
  if (!pixelAccurate()) return epsilon_;
  double nearest = INFINITY;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3d p(corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2]);
    nearest = std::min(nearest, depthOf(p));
  }
  return atDepth(nearest);
}

}  // namespace tessera
