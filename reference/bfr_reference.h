// OpenSubdiv Bfr as the exact limit-surface reference, with its approximation levels raised
// (docs/DECISIONS.md "References in tests": at the default of 2 Bfr itself is ~1e-4 of the
// diagonal off near EVs).
#pragma once

#include <map>
#include <memory>
#include <vector>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>

#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"
#include "core/topology/far_topology.h"

namespace tessera::testing {

class BfrReference {
 public:
  explicit BfrReference(const ControlMesh& mesh, int approxLevel = 10);

  // Limit position at (s, t) of a patch domain; false for a hole or a face without a surface.
  bool evaluate(const PatchDomain& domain, double s, double t, Vec3d& position);
  // Limit position at face parameter (u, v) of a base face (sub-face coordinates for n-gons).
  bool evaluateFace(int face, int subFace, double u, double v, Vec3d& position, Vec3d* du = nullptr,
                    Vec3d* dv = nullptr);
  // The mesh's UVs (face-varying channel 0) at face parameter (u, v); false for a hole.
  bool evaluateUv(int face, int subFace, double u, double v, double uv[2]);

 private:
  struct FaceSurface {
    OpenSubdiv::Bfr::Surface<double> surface;
    std::vector<double> patchPoints;
  };
  FaceSurface* surfaceOf(int face);
  FaceSurface* uvSurfaceOf(int face);

  std::vector<double> meshPoints_, meshUvs_;
  std::unique_ptr<Far::TopologyRefiner> refiner_;
  std::unique_ptr<OpenSubdiv::Bfr::RefinerSurfaceFactory<>> factory_;
  std::map<int, std::unique_ptr<FaceSurface>> surfaces_, uvSurfaces_;
};

}  // namespace tessera::testing
