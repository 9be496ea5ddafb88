// The canonical pieces a control mesh reduces to (paper §3.2): regular bicubic B-spline patches
// and extraordinary rings in CER, each with the part of a base face it covers. Together they
// cover every non-hole face of the limit surface exactly once.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/base/vec3.h"
#include "core/rings/cer_layout.h"
#include "core/rings/fas_rules.h"

namespace tessera {

// Affine map from a patch's (s, t) in [0,1]² to the parameter (u, v) of a base face, in Bfr's
// parameterization: the face's own [0,1]² for quads, the normalized quad sub-face `subFace`
// of an n-gon otherwise.
struct PatchDomain {
  int baseFace = 0;
  int subFace = -1;
  double origin[2] = {0, 0};
  double axisS[2] = {1, 0};
  double axisT[2] = {0, 1};

  void map(double s, double t, double& u, double& v) const {
    u = origin[0] + s * axisS[0] + t * axisT[0];
    v = origin[1] + s * axisS[1] + t * axisT[1];
  }
  // The sub-domain [s0, s0+size] × [t0, t0+size] of this one. Inline, so that walks whose
  // consumers ignore domains (the uniform grid) compile it away.
  PatchDomain restrict(double s0, double t0, double size) const {
    PatchDomain d = *this;
    map(s0, t0, d.origin[0], d.origin[1]);
    for (int k = 0; k < 2; ++k) {
      d.axisS[k] = axisS[k] * size;
      d.axisT[k] = axisT[k] * size;
    }
    return d;
  }
};

using ControlNet = std::array<Vec3, 16>;

struct RegularPatches {
  std::vector<ControlNet> bspline;  // row-major 4×4 B-spline nets, phantom points filled in
  std::vector<PatchDomain> domains;
  std::vector<uint8_t> levels;  // Far refinement level the patch was found at
  size_t size() const { return bspline.size(); }
};

// Extraordinary rings, each stored in CER relative to its centre (the EV's control point), so
// that deep FAS levels keep single-precision accuracy near the EV.
struct RingSet {
  std::vector<cer::RingShape> shapes;
  std::vector<uint8_t> cornerEv;
  std::vector<uint8_t> levels;     // Far refinement level the ring was taken at
  std::vector<int> pointOffsets;   // into points, ring r starts at pointOffsets[r]
  std::vector<float> points;       // xyz per point, relative to centers[r]
  std::vector<Vec3> centers;
  std::vector<int> spokeOffsets;   // into sharpSpokes
  std::vector<uint8_t> sharpSpokes;
  std::vector<int> sectorOffsets;  // into sectorDomains and sectorOwned
  std::vector<PatchDomain> sectorDomains;  // sector i's face in its lattice frame
  // Whether the ring covers sector i's face; faces Far already made regular patches, and holes,
  // belong to their own pieces (a corner where creases meet has both kinds around it).
  std::vector<uint8_t> sectorOwned;

  size_t size() const { return shapes.size(); }
  RingRules rules(size_t r) const {
    return makeRingRules(shapes[r], sharpSpokes.data() + spokeOffsets[r], cornerEv[r] != 0);
  }
  const float* ringPoints(size_t r) const { return points.data() + 3 * size_t(pointOffsets[r]); }
};

struct PatchSetStats {
  int isolationLevel = 0;
  int locallyRefinedFaces = 0;  // base faces that needed at least one level of refinement
  int holes = 0;
  int nonManifoldEdges = 0, nonManifoldVertices = 0;  // where the mesh was cut into sheets
};

struct AdaptiveSurface;  // core/surface/adaptive_surface.h
class LimitUvs;          // core/topology/limit_uvs.h

struct PatchSet {
  RegularPatches regular;
  RingSet rings;
  PatchSetStats stats;
  Vec3 boundsMin, boundsMax;
  // The surface tree and seams the adaptive tessellation plans over (built with the patch set).
  std::shared_ptr<const AdaptiveSurface> adaptive;
  // The mesh's UVs on the limit surface; null when it has none.
  std::shared_ptr<const LimitUvs> uvs;
};

}  // namespace tessera
