#include "reference/limit_surface.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace tessera::testing {

namespace Bfr = OpenSubdiv::Bfr;

namespace {

double boundingBoxDiagonal(const std::vector<Vec3>& points) {
  double lo[3], hi[3];
  std::fill(lo, lo + 3, std::numeric_limits<double>::max());
  std::fill(hi, hi + 3, std::numeric_limits<double>::lowest());
  for (const Vec3& p : points) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double(p[k]));
      hi[k] = std::max(hi[k], double(p[k]));
    }
  }
  if (points.empty()) return 0;
  return length(Vec3d(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
}

bool hasInteriorValence2(const Far::TopologyLevel& level) {
  for (int v = 0; v < level.GetNumVertices(); ++v) {
    if (level.GetVertexEdges(v).size() == 2 && !level.IsVertexBoundary(v)) return true;
  }
  return false;
}

}  // namespace

bool hasInteriorValence2(const ControlMesh& mesh) {
  return hasInteriorValence2(createTopologyRefiner(mesh)->GetLevel(0));
}

std::vector<bool> facesWithoutSurface(const ControlMesh& mesh) {
  const std::unique_ptr<Far::TopologyRefiner> refiner = createTopologyRefiner(mesh);
  std::vector<bool> hole(mesh.faceCount());
  for (int f = 0; f < mesh.faceCount(); ++f) hole[f] = refiner->GetLevel(0).IsFaceHole(f);
  return hole;
}

LimitSurface::LimitSurface(const ControlMesh& mesh)
    : LimitSurface(mesh, hasInteriorValence2(mesh) ? Backend::kFar : Backend::kBfr) {}

LimitSurface::LimitSurface(const ControlMesh& mesh, Backend backend)
    : backend_(backend),
      diagonal_(boundingBoxDiagonal(mesh.positions)),
      refiner_(createTopologyRefiner(mesh)) {
  const std::vector<bool> hole = facesWithoutSurface(mesh);
  firstDomain_.assign(mesh.faceCount(), -1);
  for (int f = 0; f < mesh.faceCount(); ++f) {
    if (hole[f]) continue;
    firstDomain_[f] = int(domains_.size());
    const int n = mesh.faceSizes[f];
    if (n == 4) {
      domains_.push_back({f, -1});
    } else {
      for (int k = 0; k < n; ++k) domains_.push_back({f, k});
    }
  }
  // Debian's Bfr 3.5.0 does not only mis-evaluate next to an interior valence-2 vertex: its
  // irregular patch builder reads out of bounds there (valgrind), and crashes in some runs.
  if (backend_ == Backend::kBfr && hasInteriorValence2(baseLevel())) {
    throw std::invalid_argument(
        "Bfr 3.5.0 cannot evaluate meshes with interior valence-2 vertices; use Far");
  }
  if (backend_ == Backend::kFar) {
    far_ = std::make_unique<FarPatchReference>(mesh);
  } else {
    prepareBfr(mesh);
  }
}

LimitSurface::~LimitSurface() = default;

// InitVertexSurface is not thread-safe with the factory's default cache, so every surface is
// built here, once; evaluation afterwards only reads.
void LimitSurface::prepareBfr(const ControlMesh& mesh) {
  Bfr::SurfaceFactory::Options options;
  options.SetApproxLevelSmooth(kApproxLevel).SetApproxLevelSharp(kApproxLevel);
  factory_ = std::make_unique<Bfr::RefinerSurfaceFactory<>>(*refiner_, options);
  faces_.resize(mesh.faceCount());
  for (int f = 0; f < mesh.faceCount(); ++f) {
    if (isHole(f)) continue;
    if (!factory_->InitVertexSurface(f, &faces_[f].surface)) {
      throw std::runtime_error("Bfr has no limit surface for face " + std::to_string(f));
    }
  }
  std::vector<double> meshPoints;
  meshPoints.reserve(3 * mesh.positions.size());
  for (const Vec3& p : mesh.positions) meshPoints.insert(meshPoints.end(), {p.x, p.y, p.z});
  tbb::parallel_for(0, mesh.faceCount(), [&](int f) {
    if (isHole(f)) return;
    FaceSurface& face = faces_[f];
    face.patchPoints.resize(size_t(face.surface.GetNumPatchPoints()) * 3);
    face.surface.PreparePatchPoints(meshPoints.data(), 3, face.patchPoints.data(), 3);
  });
  // Sub-face coordinates are an affine image of Bfr's face coordinates (a tile per sub-face);
  // keeping the map lets derivatives be returned in the domain's own coordinates.
  subFaceMaps_.resize(domains_.size());
  for (size_t d = 0; d < domains_.size(); ++d) {
    if (domains_[d].subFace < 0) continue;
    const Bfr::Parameterization param = faces_[domains_[d].face].surface.GetParameterization();
    double zero[2] = {0, 0}, one[2] = {1, 1}, at0[2], at1[2];
    param.ConvertNormalizedSubFaceToCoord(domains_[d].subFace, zero, at0);
    param.ConvertNormalizedSubFaceToCoord(domains_[d].subFace, one, at1);
    subFaceMaps_[d] = {{at0[0], at0[1]}, {at1[0] - at0[0], at1[1] - at0[1]}};
  }
}

int LimitSurface::domainOf(int face, int subFace) const {
  if (face < 0 || face >= int(firstDomain_.size()) || firstDomain_[face] < 0) return -1;
  const int size = baseLevel().GetFaceVertices(face).size();
  if (size == 4) return subFace == -1 ? firstDomain_[face] : -1;
  return subFace >= 0 && subFace < size ? firstDomain_[face] + subFace : -1;
}

int LimitSurface::continueDomain(int domain, double& u, double& v) const {
  const LimitDomain& d = domains_[domain];
  if (d.subFace >= 0 && (u > 1) != (v > 1)) {
    const int size = baseLevel().GetFaceVertices(d.face).size();
    const int first = domain - d.subFace;
    const double a = u, b = v;
    if (b > 1) {
      domain = first + (d.subFace + size - 1) % size, u = 2 - b, v = a;
    } else {
      domain = first + (d.subFace + 1) % size, u = b, v = 2 - a;
    }
  }
  u = std::clamp(u, 0.0, 1.0), v = std::clamp(v, 0.0, 1.0);
  return domain;
}

void LimitSurface::evaluate(int domain, double u, double v, Vec3d& position, Vec3d* du,
                            Vec3d* dv) const {
  const LimitDomain& d = domains_[domain];
  if (far_) {
    far_->evaluateFace(d.face, d.subFace, u, v, position, du, dv);
    return;
  }
  const SubFaceMap& map = subFaceMaps_[domain];  // identity for quads
  const double uv[2] = {map.origin[0] + map.scale[0] * u, map.origin[1] + map.scale[1] * v};
  const FaceSurface& face = faces_[d.face];
  double p[3], pu[3], pv[3];
  if (du == nullptr && dv == nullptr) {  // positions alone cost a third of the point combinations
    face.surface.Evaluate(uv, face.patchPoints.data(), 3, p);
    position = Vec3d(p[0], p[1], p[2]);
    return;
  }
  face.surface.Evaluate(uv, face.patchPoints.data(), 3, p, pu, pv);
  position = Vec3d(p[0], p[1], p[2]);
  if (du) *du = Vec3d(pu[0], pu[1], pu[2]) * map.scale[0];
  if (dv) *dv = Vec3d(pv[0], pv[1], pv[2]) * map.scale[1];
}

}  // namespace tessera::testing
