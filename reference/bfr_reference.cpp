#include "reference/bfr_reference.h"

namespace tessera::testing {

namespace Bfr = OpenSubdiv::Bfr;

BfrReference::BfrReference(const ControlMesh& mesh, int approxLevel)
    : meshUvs_(mesh.uvs.begin(), mesh.uvs.end()), refiner_(createTopologyRefiner(mesh, /*withUvs=*/true)) {
  for (const Vec3& p : mesh.positions) meshPoints_.insert(meshPoints_.end(), {p.x, p.y, p.z});
  Bfr::SurfaceFactory::Options options;
  options.SetApproxLevelSmooth(approxLevel).SetApproxLevelSharp(approxLevel);
  factory_ = std::make_unique<Bfr::RefinerSurfaceFactory<>>(*refiner_, options);
}

BfrReference::FaceSurface* BfrReference::surfaceOf(int face) {
  auto found = surfaces_.find(face);
  if (found != surfaces_.end()) return found->second.get();
  auto entry = std::make_unique<FaceSurface>();
  if (!factory_->InitVertexSurface(face, &entry->surface)) {
    surfaces_[face] = nullptr;
    return nullptr;
  }
  entry->patchPoints.resize(size_t(entry->surface.GetNumPatchPoints()) * 3);
  entry->surface.PreparePatchPoints(meshPoints_.data(), 3, entry->patchPoints.data(), 3);
  return (surfaces_[face] = std::move(entry)).get();
}

BfrReference::FaceSurface* BfrReference::uvSurfaceOf(int face) {
  auto found = uvSurfaces_.find(face);
  if (found != uvSurfaces_.end()) return found->second.get();
  auto entry = std::make_unique<FaceSurface>();
  if (!factory_->InitFaceVaryingSurface(face, &entry->surface, 0)) {
    uvSurfaces_[face] = nullptr;
    return nullptr;
  }
  entry->patchPoints.resize(size_t(entry->surface.GetNumPatchPoints()) * 2);
  entry->surface.PreparePatchPoints(meshUvs_.data(), 2, entry->patchPoints.data(), 2);
  return (uvSurfaces_[face] = std::move(entry)).get();
}

bool BfrReference::evaluateUv(int face, int subFace, double u, double v, double uv[2]) {
  FaceSurface* s = uvSurfaceOf(face);
  if (s == nullptr) return false;
  double at[2] = {u, v};
  if (subFace >= 0) {
    const double sub[2] = {u, v};
    s->surface.GetParameterization().ConvertNormalizedSubFaceToCoord(subFace, sub, at);
  }
  s->surface.Evaluate(at, s->patchPoints.data(), 2, uv);
  return true;
}

bool BfrReference::evaluateFace(int face, int subFace, double u, double v, Vec3d& position,
                                Vec3d* du, Vec3d* dv) {
  FaceSurface* s = surfaceOf(face);
  if (s == nullptr) return false;
  double uv[2] = {u, v};
  if (subFace >= 0) {
    double sub[2] = {u, v};
    s->surface.GetParameterization().ConvertNormalizedSubFaceToCoord(subFace, sub, uv);
  }
  double p[3], pu[3], pv[3];
  s->surface.Evaluate(uv, s->patchPoints.data(), 3, p, pu, pv);
  position = Vec3d(p[0], p[1], p[2]);
  if (du) *du = Vec3d(pu[0], pu[1], pu[2]);
  if (dv) *dv = Vec3d(pv[0], pv[1], pv[2]);
  return true;
}

bool BfrReference::evaluate(const PatchDomain& domain, double s, double t, Vec3d& position) {
  double u, v;
  domain.map(s, t, u, v);
  return evaluateFace(domain.baseFace, domain.subFace, u, v, position);
}

}  // namespace tessera::testing
