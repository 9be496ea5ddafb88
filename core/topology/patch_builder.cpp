// Preprocessing (paper §3.2, docs/DECISIONS.md "Preprocessing"): OpenSubdiv's adaptive refinement
// isolates every irregular feature; its patch table then names the regular B-spline patches,
// and the faces left irregular at the last level (its end caps) are exactly the inner faces of
// extraordinary rings, which we gather in CER order with the lattice walker.
#include "core/topology/patch_builder.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <string>

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>

#include "core/base/error.h"
#include "core/topology/far_topology.h"
#include "core/topology/limit_uvs.h"
#include "core/topology/refinement_budget.h"
#include "core/topology/refinement_input.h"
#include "core/topology/ring_extraction.h"

namespace tessera {

using Far::Index;

namespace {

struct PtexFace {
  int baseFace;
  int subFace;
};

std::vector<PtexFace> ptexFaces(const Far::TopologyRefiner& refiner) {
  Far::PtexIndices ptex(refiner);
  const auto& base = refiner.GetLevel(0);
  std::vector<PtexFace> result(ptex.GetNumFaces());
  for (int f = 0; f < base.GetNumFaces(); ++f) {
    int first = ptex.GetFaceId(f);
    int size = base.GetFaceVertices(f).size();
    if (size == 4) {
      result[first] = {f, -1};
    } else {
      for (int k = 0; k < size; ++k) result[first + k] = {f, k};
    }
  }
  return result;
}

PatchDomain domainOf(const Far::PatchParam& param, const std::vector<PtexFace>& ptex) {
  PatchDomain d;
  d.baseFace = ptex[param.GetFaceId()].baseFace;
  d.subFace = ptex[param.GetFaceId()].subFace;
  double u0 = 0, v0 = 0, u1 = 1, v1 = 1;
  param.Unnormalize(u0, v0);
  param.Unnormalize(u1, v1);
  d.origin[0] = u0, d.origin[1] = v0;
  d.axisS[0] = u1 - u0, d.axisS[1] = 0;
  d.axisT[0] = 0, d.axisT[1] = v1 - v0;
  return d;
}

// Lattice frame of a ring sector: the face's corner `rotation` is the EV (lattice origin).
// Corners (0,0),(1,0),(1,1),(0,1) of the face's parameter square follow its vertex order.
PatchDomain rotateToLattice(const PatchDomain& face, int rotation) {
  static const double kCorner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const double* o = kCorner[rotation % 4];
  const double* x = kCorner[(rotation + 1) % 4];
  const double* y = kCorner[(rotation + 3) % 4];
  PatchDomain d = face;
  face.map(o[0], o[1], d.origin[0], d.origin[1]);
  double xu, xv, yu, yv;
  face.map(x[0], x[1], xu, xv);
  face.map(y[0], y[1], yu, yv);
  d.axisS[0] = xu - d.origin[0], d.axisS[1] = xv - d.origin[1];
  d.axisT[0] = yu - d.origin[0], d.axisT[1] = yv - d.origin[1];
  return d;
}

// Phantom points of boundary patches (boundary bits: v=0, u=1, v=1, u=0): reflect across the
// boundary, 2·p_edge − p_inner, which is the extrapolation Far's boundary basis encodes.
void fillPhantoms(ControlNet& net, int boundaryMask) {
  auto at = [&](int row, int col) -> Vec3& { return net[4 * row + col]; };
  for (int i = 0; i < 4; ++i) {
    if (boundaryMask & 1) at(0, i) = at(1, i) * 2.0f - at(2, i);
    if (boundaryMask & 4) at(3, i) = at(2, i) * 2.0f - at(1, i);
  }
  for (int i = 0; i < 4; ++i) {
    if (boundaryMask & 8) at(i, 0) = at(i, 1) * 2.0f - at(i, 2);
    if (boundaryMask & 2) at(i, 3) = at(i, 2) * 2.0f - at(i, 1);
  }
}

// A vertex whose neighbourhood is not a regular B-spline configuration: wrong valence, a
// sharp or semi-sharp feature other than a straight infinitely sharp crease or boundary.
bool isIrregularVertex(const Far::TopologyLevel& level, Index v) {
  const bool boundary = level.IsVertexBoundary(v);
  if (level.GetVertexFaces(v).size() != (boundary ? 2 : 4)) return true;
  if (level.GetVertexSharpness(v) > 0.0f) return true;
  auto edges = level.GetVertexEdges(v);
  int sharpCount = 0, firstSharp = -1, lastSharp = -1;
  for (int k = 0; k < edges.size(); ++k) {
    bool sharp = level.IsEdgeInfSharp(edges[k]) || level.IsEdgeBoundary(edges[k]);
    if (!sharp && level.GetEdgeSharpness(edges[k]) > 0.0f) return true;
    if (!sharp) continue;
    ++sharpCount;
    (firstSharp < 0 ? firstSharp : lastSharp) = k;
  }
  if (sharpCount == 0) return false;
  if (sharpCount != 2) return true;
  return !boundary && lastSharp - firstSharp != 2;  // an interior crease must run straight
}

class PatchSetBuilder {
 public:
  PatchSetBuilder(const ControlMesh& mesh, const RefinementInput& input, const PreprocessingOptions& options)
      : mesh_(mesh),
        input_(input),
        checkpoint_(options.checkpoint),
        maxRefinedVertices_(options.maxRefinedVertices),
        beforeRefining_(options.beforeRefining),
        afterRefining_(options.afterRefining) {}
  PatchSet build();

 private:
  void addRegularPatch(Far::ConstIndexArray cvs, const Far::PatchParam& param);
  void addEndCap(const Far::PatchParam& param);
  void refineAndGather(const ControlMesh& far, int isolation);
  void buildRings();
  void addRing(int level, Index ev);

  void checkpointNow() const {
    if (checkpoint_) checkpoint_();
  }

  const ControlMesh& mesh_;
  const RefinementInput& input_;  // what OpenSubdiv refines
  const std::function<void()>& checkpoint_;
  const int64_t maxRefinedVertices_;
  const std::function<void(int64_t)> beforeRefining_;
  const std::function<void(int64_t)> afterRefining_;
  std::unique_ptr<Far::TopologyRefiner> refiner_;
  std::vector<Vec3d> positions_;
  std::vector<int> levelOffsets_;
  std::vector<PtexFace> ptex_;
  // End-cap faces per level, with the domain of the face's parameter square.
  std::vector<std::map<Index, PatchDomain>> endCaps_;
  PatchSet result_;
};

void PatchSetBuilder::addRegularPatch(Far::ConstIndexArray cvs, const Far::PatchParam& param) {
  ControlNet net;
  for (int i = 0; i < 16; ++i) net[i] = Vec3(positions_[cvs[i]]);
  fillPhantoms(net, param.GetBoundary());
  result_.regular.bspline.push_back(net);
  result_.regular.domains.push_back(domainOf(param, ptex_));
  result_.regular.levels.push_back(static_cast<uint8_t>(param.GetDepth()));
}

// End caps carry their own local points, so find the refined face from the patch parameter:
// descend from the base face (or its quad sub-face) by one quadrant bit of (u, v) per level.
// Child face j of a quad sits at the parent's corner j, corners ordered (0,0),(1,0),(1,1),(0,1).
void PatchSetBuilder::addEndCap(const Far::PatchParam& param) {
  const PtexFace& ptexFace = ptex_[param.GetFaceId()];
  int depth = param.GetDepth();
  int level = 0;
  Index face = ptexFace.baseFace;
  if (param.NonQuadRoot()) {
    face = refiner_->GetLevel(0).GetFaceChildFaces(face)[ptexFace.subFace];
    level = 1;
  }
  static const int kQuadrantChild[2][2] = {{0, 3}, {1, 2}};  // [u bit][v bit]
  for (; level < depth; ++level) {
    int shift = depth - level - 1;
    int child = kQuadrantChild[(param.GetU() >> shift) & 1][(param.GetV() >> shift) & 1];
    face = refiner_->GetLevel(level).GetFaceChildFaces(face)[child];
  }
  if (face < 0) throwUnsupported("internal: an irregular patch does not match a refined face");
  endCaps_[depth][face] = domainOf(param, ptex_);
}

void PatchSetBuilder::addRing(int levelIndex, Index ev) {
  RefinedMesh refined{*refiner_, positions_, levelOffsets_};
  GatheredRing gathered = extractRing(refined, levelIndex, ev);
  RingSet& rings = result_.rings;
  const Vec3d center = gathered.points[0];
  rings.shapes.push_back(gathered.shape);
  rings.cornerEv.push_back(gathered.cornerEv ? 1 : 0);
  rings.levels.push_back(static_cast<uint8_t>(levelIndex));
  rings.pointOffsets.push_back(static_cast<int>(rings.points.size() / 3));
  for (const Vec3d& point : gathered.points) {
    Vec3d p = point - center;
    rings.points.insert(rings.points.end(), {float(p.x), float(p.y), float(p.z)});
  }
  rings.centers.push_back(Vec3(center));
  rings.spokeOffsets.push_back(static_cast<int>(rings.sharpSpokes.size()));
  rings.sharpSpokes.insert(rings.sharpSpokes.end(), gathered.sharpSpokes.begin(),
                           gathered.sharpSpokes.end());
  rings.sectorOffsets.push_back(static_cast<int>(rings.sectorDomains.size()));
  for (int i = 0; i < gathered.shape.sectors; ++i) {
    auto found = endCaps_[levelIndex].find(gathered.sectorFaces[i]);
    bool owned = found != endCaps_[levelIndex].end();
    rings.sectorOwned.push_back(owned ? 1 : 0);
    rings.sectorDomains.push_back(owned ? rotateToLattice(found->second, gathered.sectorRotations[i])
                                        : PatchDomain{});
  }
}

// Each end-cap face has exactly one irregular corner, its ring's EV. A ring owns the sectors
// whose faces are end caps; its other sectors are regular patches or holes, covered elsewhere.
void PatchSetBuilder::buildRings() {
  for (int levelIndex = 0; levelIndex < int(endCaps_.size()); ++levelIndex) {
    const auto& level = refiner_->GetLevel(levelIndex);
    std::set<Index> evs;
    for (const auto& [face, domain] : endCaps_[levelIndex]) {
      int candidates = 0;
      for (Index v : level.GetFaceVertices(face)) {
        if (!isIrregularVertex(level, v)) continue;
        evs.insert(v);
        ++candidates;
      }
      if (candidates != 1) {
        throwUnsupported("refined face " + std::to_string(face) + " at level " +
                         std::to_string(levelIndex) + " of base face " +
                         std::to_string(domain.baseFace) + " has " + std::to_string(candidates) +
                         " irregular corners after isolation; only isolated features are supported");
      }
    }
    for (Index ev : evs) {
      checkpointNow();
      addRing(levelIndex, ev);
    }
  }
}

// Far's refinement of `far` (the sheets, or the sheets without their hole tags), its regular
// patches and the rings of its end caps; pieces of the sheets' holes are dropped.
void PatchSetBuilder::refineAndGather(const ControlMesh& far, int isolation) {
  refiner_ = createTopologyRefiner(far);
  const Far::PatchTableFactory::Options options = patchTableOptions(isolation);
  refineAdaptively(*refiner_, options);
  checkpointNow();
  if (afterRefining_) afterRefining_(refiner_->GetNumVerticesTotal());
  std::unique_ptr<Far::PatchTable> table(Far::PatchTableFactory::Create(*refiner_, options));
  checkpointNow();

  positions_ = refinedPositions(*refiner_, far.positions);
  levelOffsets_.assign(1, 0);
  for (int l = 0; l < refiner_->GetMaxLevel(); ++l) {
    levelOffsets_.push_back(levelOffsets_.back() + refiner_->GetLevel(l).GetNumVertices());
  }
  ptex_ = ptexFaces(*refiner_);
  endCaps_.assign(refiner_->GetMaxLevel() + 1, {});
  std::vector<uint8_t> hole(far.faceCount(), 0);
  for (int f : input_.sheets().holes) hole[f] = 1;

  for (int array = 0; array < table->GetNumPatchArrays(); ++array) {
    auto type = table->GetPatchArrayDescriptor(array).GetType();
    for (int p = 0; p < table->GetNumPatches(array); ++p) {
      auto cvs = table->GetPatchVertices(array, p);
      auto param = table->GetPatchParam(array, p);
      if (hole[ptex_[param.GetFaceId()].baseFace]) continue;
      if (type == Far::PatchDescriptor::REGULAR) {
        addRegularPatch(cvs, param);
      } else if (type == Far::PatchDescriptor::QUADS) {
        addEndCap(param);
      } else {
        throwUnsupported("internal: unexpected OpenSubdiv patch type");
      }
    }
  }
  buildRings();
}

PatchSet PatchSetBuilder::build() {
  const ControlMesh& sheets = input_.sheets();
  checkpointNow();
  const int isolation = isolationLevelFor(sheets);
  if (maxRefinedVertices_ > 0 || beforeRefining_) {
    // Without a limit the estimate is still wanted: one far beyond any machine's memory.
    const int64_t limit = maxRefinedVertices_ > 0 ? maxRefinedVertices_ : int64_t(1) << 50;
    const int64_t estimate = requireRefinementWithin(input_.unholed(), limit, checkpoint_);
    if (beforeRefining_) beforeRefining_(estimate);
  }
  try {
    refineAndGather(sheets, isolation);
  } catch (const TesseraError& error) {
    if (sheets.holes.empty() || error.kind() != ErrorKind::kUnsupported) throw;
    // Far's sparse levels leave hole faces out: a ring beside a hole can lack its lattice, or see
    // a semi-sharp edge of the hole that Far stopped isolating. Refined again as if there were no
    // holes (a hole changes no refinement rule), with the holes' pieces dropped, every ring is
    // complete and isolated. Not the first choice: the refined hole faces also split their
    // neighbours' patches (catmark_hole_test1 at 1e-3: 29 % more triangles).
    result_.regular = {};
    result_.rings = {};
    refineAndGather(input_.unholed(), isolation);
  }

  result_.stats.isolationLevel = isolation;
  result_.stats.holes = static_cast<int>(mesh_.holes.size());
  result_.stats.nonManifoldEdges = input_.cut().nonManifoldEdges;
  result_.stats.nonManifoldVertices = input_.cut().nonManifoldVertices;
  std::set<int> refinedBaseFaces;
  for (size_t p = 0; p < result_.regular.size(); ++p) {
    if (result_.regular.levels[p] > 0) refinedBaseFaces.insert(result_.regular.domains[p].baseFace);
  }
  for (size_t i = 0; i < result_.rings.sectorDomains.size(); ++i) {
    if (result_.rings.sectorOwned[i]) refinedBaseFaces.insert(result_.rings.sectorDomains[i].baseFace);
  }
  result_.stats.locallyRefinedFaces = static_cast<int>(refinedBaseFaces.size());
  mesh_.bounds(result_.boundsMin, result_.boundsMax);
  if (mesh_.hasUvs()) result_.uvs = std::make_shared<const LimitUvs>(mesh_);
  return std::move(result_);
}

}  // namespace

PatchSet reduceToPatches(const ControlMesh& mesh, const RefinementInput& input, const PreprocessingOptions& options) {
  return PatchSetBuilder(mesh, input, options).build();
}

}  // namespace tessera
