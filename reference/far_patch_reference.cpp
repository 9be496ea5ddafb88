#include "reference/far_patch_reference.h"

#include <opensubdiv/far/patchTableFactory.h>

namespace tessera::testing {

namespace {
struct Point {
  Vec3d p;
  void Clear() { p = Vec3d(); }
  void AddWithWeight(const Point& src, double w) { p += src.p * w; }
};
}  // namespace

FarPatchReference::FarPatchReference(const ControlMesh& mesh, int isolationLevel)
    : refiner_(createTopologyRefiner(mesh)) {
  Far::PatchTableFactory::Options options(isolationLevel);
  options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
  options.useInfSharpPatch = true;
  options.generateLegacySharpCornerPatches = false;
  options.SetPatchPrecision<double>();
  refiner_->RefineAdaptive(options.GetRefineAdaptiveOptions());
  table_.reset(Far::PatchTableFactory::Create(*refiner_, options));
  map_ = std::make_unique<Far::PatchMap>(*table_);
  ptex_ = std::make_unique<Far::PtexIndices>(*refiner_);
  std::vector<Vec3d> refined = refinedPositions(*refiner_, mesh.positions);
  std::vector<Point> all(refined.size() + table_->GetNumLocalPoints());
  for (size_t i = 0; i < refined.size(); ++i) all[i].p = refined[i];
  if (const auto* stencils = table_->GetLocalPointStencilTable<double>()) {
    stencils->UpdateValues(all.data(), all.data() + refined.size());
  }
  for (const Point& p : all) points_.push_back(p.p);
}

bool FarPatchReference::evaluate(const PatchDomain& domain, double s, double t, Vec3d& position) const {
  double u, v;
  domain.map(s, t, u, v);
  return evaluateFace(domain.baseFace, domain.subFace, u, v, position);
}

// Far's Ptex faces are the quads and the normalized sub-faces of every other face, in order, so
// (face, subFace, u, v) is a Ptex coordinate; EvaluateBasis returns derivatives in it.
bool FarPatchReference::evaluateFace(int face, int subFace, double u, double v, Vec3d& position,
                                     Vec3d* du, Vec3d* dv) const {
  int ptexFace = ptex_->GetFaceId(face) + (subFace < 0 ? 0 : subFace);
  const Far::PatchTable::PatchHandle* handle = map_->FindPatch(ptexFace, u, v);
  if (handle == nullptr) return false;
  double w[20], wu[20], wv[20];
  table_->EvaluateBasis(*handle, u, v, w, wu, wv);
  auto cvs = table_->GetPatchVertices(*handle);
  position = Vec3d();
  Vec3d pu, pv;
  for (int i = 0; i < cvs.size(); ++i) {
    position += points_[cvs[i]] * w[i];
    pu += points_[cvs[i]] * wu[i];
    pv += points_[cvs[i]] * wv[i];
  }
  // EvaluateBasis scales derivatives by 2^depth, but a non-quad's Ptex sub-face already starts at
  // depth 1 (measured against finite differences: twice the true derivative on every sub-face).
  const double scale = table_->GetPatchParam(*handle).NonQuadRoot() ? 0.5 : 1.0;
  if (du) *du = pu * scale;
  if (dv) *dv = pv * scale;
  return true;
}

}  // namespace tessera::testing
