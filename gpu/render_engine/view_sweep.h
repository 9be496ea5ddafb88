// The paper's Table 3 and Fig. 8 setup: the model centred on screen and as large as it can be
// without leaving the view, rotated about x and y at equal intervals (10 angles per axis, 100
// views), rendered pixel-accurately. Reported per model: triangles per base face, and the
// average and maximum subdivision depth around extraordinary vertices.
#pragma once

#include <vector>

#include "core/request/tessellation_options.h"
#include "core/rings/patch_set.h"

namespace tessera::gpu {

struct ViewSweep {
  int anglesPerAxis = 10;  // views = anglesPerAxis²
  int width = 1920, height = 1080;
  double fovYDegrees = 45;
  double pixelAccuracy = 0.5;
  double eta = 0.5;
};

// View (i, j), at index i·n + j: the model turned by 2πi/n about x, then by 2πj/n about y,
// around its bounding-box centre, seen from +z. Expressed as the equivalent camera orbiting the
// fixed model, as close as it can be with all eight corners of the bounding box in view (1%
// margin), so the model fills the frame without being cut. Throws TesseraError for n < 1 or a
// bad viewport / field of view.
std::vector<tessera::Camera> sweepCameras(const PatchSet& patches, const ViewSweep& sweep);

struct SweepStatistics {
  int views = 0;
  double averageTrianglesPerBaseFace = 0;  // rendered triangles / non-hole base faces
  double averageTriangles = 0;
  double averagePieces = 0;
  double averageRingDepth = 0;  // FAS steps chosen per ring (Eq. (4)), over rings and views
  int maxRingDepth = 0;
  double averageRingLevel = 0;  // Far isolation level + FAS steps (level below the base face)
  int maxRingLevel = 0;
  double averagePlanMs = 0;  // planTessellation per view, CPU
};

// Table 3 on the CPU (planning and patch preparation only, nothing is drawn): the triangles are
// those the renderer would draw for the visible pieces. `baseFaces`: the control mesh's faces
// that are not holes.
SweepStatistics sweepStatistics(const PatchSet& patches, int baseFaces, const ViewSweep& sweep);

}  // namespace tessera::gpu
