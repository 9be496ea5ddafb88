// The exact Catmull-Clark limit surface of a control mesh as a set of parameter domains, prepared
// once and then evaluated from any number of threads: the reference that measured distances
// (reference/limit_distance.h) and oracle tessellations (reference/uniform_tessellation.h)
// are taken against.
//
// Domains are BfrReference::evaluateFace's: a quad is one domain (u, v) in [0,1]^2 (sub-face -1),
// every other face is one domain per normalized quad sub-face k (corner k at (0,0), the midpoint
// of edge k at (1,0), the face centre at (1,1), the midpoint of edge k-1 at (0,1)). Holes have no
// domain.
//
// Evaluation is OpenSubdiv Bfr with approximation levels raised to 6 (smooth and sharp); Debian's
// Bfr 3.5.0 mis-evaluates around interior valence-2 vertices (DECISIONS.md), so meshes with one
// use Far's patch table instead (FarPatchReference, isolation level 10).
#pragma once

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>

#include <memory>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/topology/far_topology.h"
#include "reference/far_patch_reference.h"

namespace tessera::testing {

struct LimitDomain {
  int face = 0;
  int subFace = -1;  // -1 for a quad, else the normalized sub-face
};

// True when some vertex has exactly two edges and is not on a boundary.
bool hasInteriorValence2(const ControlMesh& mesh);

// Per base face, whether it has no limit surface: its hole tag, or Far's tag for a face at a
// boundary vertex under VTX_BOUNDARY_NONE.
std::vector<bool> facesWithoutSurface(const ControlMesh& mesh);

class LimitSurface {
 public:
  enum class Backend { kBfr, kFar };
  // Bfr approximates the surface within 2^-level of an irregular feature. Level 6 is not enough
  // for 1e-4 of the diagonal: it is off by about that much next to the characters' extraordinary
  // vertices, and by 7e-4 (rook) to 1.6e-3 (bishop) where semi-sharp creases of sharpness above
  // 6 meet; at 10 it agrees with level 12 within 3e-6 on the benchmark models.
  static constexpr int kApproxLevel = 10;
  // What a distance measured against it may be off by, as a fraction of the diagonal (level 10
  // against level 12 on the benchmark models, 3e-6, rounded up).
  static constexpr double kRelativeAccuracy = 5e-6;

  // Chooses Far when the mesh has an interior valence-2 vertex, else Bfr.
  explicit LimitSurface(const ControlMesh& mesh);
  // Throws std::invalid_argument for Bfr on a mesh with an interior valence-2 vertex (Bfr 3.5.0
  // reads out of bounds building those surfaces).
  LimitSurface(const ControlMesh& mesh, Backend backend);
  ~LimitSurface();

  Backend backend() const { return backend_; }
  const std::vector<LimitDomain>& domains() const { return domains_; }
  int domainCount() const { return int(domains_.size()); }
  // Index into domains() of (face, subFace); -1 for a hole or a pair that names no domain.
  int domainOf(int face, int subFace) const;
  // Diagonal of the control points' bounding box (what relative tolerances refer to).
  double diagonal() const { return diagonal_; }
  // The base level's topology (face vertices and edges), for tessellators sharing edges.
  const Far::TopologyLevel& baseLevel() const { return refiner_->GetLevel(0); }
  bool isHole(int face) const { return firstDomain_[face] < 0; }

  // Where (u, v), possibly outside [0,1]^2, lies: past a spoke of an n-gon's sub-face (u > 1 or
  // v > 1) the neighbouring sub-face continues the chart, unfolded as a quad's would be, so (u, v)
  // of sub-face k with v > 1 is (2 - v, u) of sub-face k - 1 and with u > 1 it is (v, 2 - u) of
  // sub-face k + 1. Returns that domain with (u, v) in it, clamped to [0,1]^2 (beyond the face
  // centre, across a face's own edges and in quads, coordinates are only clamped).
  int continueDomain(int domain, double& u, double& v) const;

  // Position and first derivatives at (u, v) in [0,1]^2 of a domain. Const and thread-safe.
  void evaluate(int domain, double u, double v, Vec3d& position, Vec3d* du = nullptr,
                Vec3d* dv = nullptr) const;

 private:
  // One Bfr surface per non-hole face, with its patch points and, for n-gons, the affine map from
  // normalized sub-face coordinates to Bfr's face coordinates (u_bfr = origin + scale * u).
  struct FaceSurface {
    OpenSubdiv::Bfr::Surface<double> surface;
    std::vector<double> patchPoints;
  };
  struct SubFaceMap {
    double origin[2] = {0, 0}, scale[2] = {1, 1};
  };
  void prepareBfr(const ControlMesh& mesh);

  Backend backend_;
  double diagonal_ = 0;
  std::unique_ptr<Far::TopologyRefiner> refiner_;
  std::unique_ptr<OpenSubdiv::Bfr::RefinerSurfaceFactory<>> factory_;  // owns shared patch trees
  std::vector<LimitDomain> domains_;
  std::vector<int> firstDomain_;  // per face; -1 for holes
  std::vector<FaceSurface> faces_;
  std::vector<SubFaceMap> subFaceMaps_;  // per domain
  std::unique_ptr<FarPatchReference> far_;
};

}  // namespace tessera::testing
