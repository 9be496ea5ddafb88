#include "gpu/render_engine/view_sweep.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/base/error.h"
#include "gpu/render_engine/frame_engine.h"

namespace tessera::gpu {
namespace {

// Rotations about x and y by angle a (radians), applied to v.
Vec3d rotateX(const Vec3d& v, double a) {
  return {v.x, std::cos(a) * v.y - std::sin(a) * v.z, std::sin(a) * v.y + std::cos(a) * v.z};
}
Vec3d rotateY(const Vec3d& v, double a) {
  return {std::cos(a) * v.x + std::sin(a) * v.z, v.y, -std::sin(a) * v.x + std::cos(a) * v.z};
}

}  // namespace

std::vector<tessera::Camera> sweepCameras(const PatchSet& patches, const ViewSweep& sweep) {
  if (sweep.anglesPerAxis < 1) {
    throwInvalid("a view sweep needs at least one angle per axis, got " +
                 std::to_string(sweep.anglesPerAxis));
  }
  if (sweep.width <= 0 || sweep.height <= 0) throwInvalid("view sweep viewport must be positive");
  if (!(sweep.fovYDegrees > 0 && sweep.fovYDegrees < 180)) {
    throwInvalid("view sweep field of view must be in (0, 180) degrees");
  }
  const Vec3d lo(patches.boundsMin), hi(patches.boundsMax);
  const Vec3d centre = (lo + hi) * 0.5;
  const double tanY = std::tan(sweep.fovYDegrees * M_PI / 360.0);
  const double tanX = tanY * sweep.width / sweep.height;
  const double extent = std::max(length(hi - lo), 1e-12);

  std::vector<tessera::Camera> cameras;
  const int n = sweep.anglesPerAxis;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      double ax = 2 * M_PI * i / n, ay = 2 * M_PI * j / n;
      // Turning the model by Ry·Rx equals turning the camera by (Ry·Rx)⁻¹ = Rx⁻¹·Ry⁻¹.
      auto inverse = [&](const Vec3d& v) { return rotateX(rotateY(v, -ay), -ax); };
      const Vec3d back = inverse(Vec3d(0, 0, 1)), up = inverse(Vec3d(0, 1, 0));
      const Vec3d right = cross(up, back);
      // The nearest eye on this axis that keeps every corner of the bounding box (which holds
      // the surface) inside the view: a corner at (x, y) across and z towards the eye from the
      // centre needs a distance d with |x| ≤ tanX·(d − z) and |y| ≤ tanY·(d − z). 1% margin.
      double distance = 0;
      for (int k = 0; k < 8; ++k) {
        Vec3d d = Vec3d(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z) - centre;
        double x = dot(d, right), y = dot(d, up), z = dot(d, back);
        distance = std::max({distance, z + std::abs(x) / tanX, z + std::abs(y) / tanY});
      }
      distance = distance * 1.01 + 1e-6 * extent;
      tessera::Camera camera;
      camera.target = centre;
      camera.eye = centre + back * distance;
      camera.up = up;
      camera.fovYDegrees = sweep.fovYDegrees;
      camera.width = sweep.width;
      camera.height = sweep.height;
      cameras.push_back(camera);
    }
  }
  return cameras;
}

SweepStatistics sweepStatistics(const PatchSet& patches, int baseFaces, const ViewSweep& sweep) {
  if (baseFaces <= 0) throwInvalid("the base face count must be positive");
  SweepStatistics out;
  double ringLevelSum = 0;
  for (const tessera::Camera& camera : sweepCameras(patches, sweep)) {
    FrameRequest request;
    request.camera = camera;
    request.accuracy = Accuracy::pixel(sweep.pixelAccuracy);
    request.eta = sweep.eta;
    request.maxTriangles = INT64_MAX;  // statistics only: nothing is allocated per triangle
    PreparedFrame frame = prepareFrame(patches, request);
    const FrameStatistics& s = frame.statistics;
    ++out.views;
    out.averageTriangles += double(s.plannedTriangles);
    out.averagePieces += double(s.pieces);
    out.averageRingDepth += s.averageRingDepth;
    out.maxRingDepth = std::max(out.maxRingDepth, s.maxRingDepth);
    ringLevelSum += s.averageRingLevel;
    out.maxRingLevel = std::max(out.maxRingLevel, s.maxRingLevel);
    out.averagePlanMs += frame.timings.planMs;
  }
  out.averageTriangles /= out.views;
  out.averagePieces /= out.views;
  out.averageRingDepth /= out.views;
  out.averageRingLevel = ringLevelSum / out.views;
  out.averagePlanMs /= out.views;
  out.averageTrianglesPerBaseFace = out.averageTriangles / baseFaces;
  return out;
}

}  // namespace tessera::gpu
