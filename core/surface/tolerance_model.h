// Object-space tolerance for a part of the surface (MATH.md §4, docs/DECISIONS.md "Pixel
// accuracy"): ε itself (absolute, or a fraction of the control mesh's bounding-box diagonal), or
// with a camera ε_obj = px · z / (f_px · √(1 + tan²(φx/2) + tan²(φy/2))) at the part's nearest
// view depth z (over its control points, or a box holding its surface), z reduced by ε_obj
// itself and clamped at a near plane at 1% of the eye–target distance. Every value is less the
// encoding's reserve (TessellationOptions::encodingReserve), which the output spends.
#pragma once

#include "core/request/tessellation_options.h"
#include "core/rings/patch_set.h"

namespace tessera {

class ToleranceModel {
 public:
  ToleranceModel(const TessellationOptions& options, const PatchSet& patches)
      : ToleranceModel(options, patches.boundsMin, patches.boundsMax) {}
  // For a mesh whose control points lie in [boundsMin, boundsMax] (its surface does too).
  ToleranceModel(const TessellationOptions& options, Vec3 boundsMin, Vec3 boundsMax);

  double forPoints(const Vec3* points, int count) const;
  // A stored ring: xyz floats relative to its centre.
  double forRing(const float* ring, int count, Vec3 center) const;
  // Any surface inside the box [lo, hi] (the depth is linear: its minimum is at a corner).
  double forBox(const float lo[3], const float hi[3]) const;
  // ε in object space without a camera (the one value for the whole surface).
  double uniform() const { return epsilon_; }
  bool pixelAccurate() const { return pixelScale_ > 0; }

 private:
  double depthOf(Vec3d point) const { return dot(point - eye_, forward_); }
  double atDepth(double nearest) const;

  double epsilon_ = 0, reserve_ = 0;
  Vec3d eye_, forward_;
  double pixelScale_ = 0, near_ = 0;
};

}  // namespace tessera
