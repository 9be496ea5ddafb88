// Preprocessing's topology (paper §3.2, docs/DECISIONS.md "Preprocessing"): OpenSubdiv's adaptive
// refinement isolates every irregular feature; its patch table then names the regular B-spline
// patches, and the faces left irregular at the last level (its end caps) are exactly the inner
// faces of extraordinary rings, which we lay out in CER order with the lattice walker.
#include "core/topology/patch_topology.h"

#include <map>
#include <set>
#include <string>
#include <string_view>

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>

#include "core/base/error.h"
#include "core/base/sha256.h"
#include "core/mesh/manifold_sheets.h"
#include "core/topology/far_topology.h"
#include "core/topology/refinement_budget.h"
#include "core/topology/refinement_input.h"

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

// The mesh's topology as a ControlMesh: its points all at the origin (their count numbers them).
ControlMesh withoutPositions(const ControlMesh& mesh) {
  ControlMesh faces;
  faces.positions.assign(mesh.positions.size(), Vec3());
  faces.faceSizes = mesh.faceSizes;
  faces.faceVertices = mesh.faceVertices;
  faces.creases = mesh.creases;
  faces.corners = mesh.corners;
  faces.holes = mesh.holes;
  faces.rules = mesh.rules;
  return faces;
}

}  // namespace

class PatchTopologyBuilder {
 public:
  PatchTopologyBuilder(PatchTopology& out, const ControlMesh& mesh, const PreprocessingOptions& options)
      : out_(out), mesh_(mesh), options_(options) {}
  void build();

 private:
  void refineAndLayOut(const ControlMesh& far, const std::vector<int>& holes, int isolation);
  void addEndCap(const Far::PatchParam& param);
  void layOutRings();
  void addRing(int level, Index ev);
  void countRefinedFaces();

  void checkpointNow() const {
    if (options_.checkpoint) options_.checkpoint();
  }

  PatchTopology& out_;
  const ControlMesh& mesh_;
  const PreprocessingOptions& options_;
  std::vector<int> levelOffsets_;
  std::vector<PtexFace> ptex_;
  // End-cap faces per level, with the domain of the face's parameter square.
  std::vector<std::map<Index, PatchDomain>> endCaps_;
};

// End caps carry their own local points, so find the refined face from the patch parameter:
// descend from the base face (or its quad sub-face) by one quadrant bit of (u, v) per level.
// Child face j of a quad sits at the parent's corner j, corners ordered (0,0),(1,0),(1,1),(0,1).
void PatchTopologyBuilder::addEndCap(const Far::PatchParam& param) {
  const PtexFace& ptexFace = ptex_[param.GetFaceId()];
  int depth = param.GetDepth();
  int level = 0;
  Index face = ptexFace.baseFace;
  const Far::TopologyRefiner& refiner = *out_.refiner_;
  if (param.NonQuadRoot()) {
    face = refiner.GetLevel(0).GetFaceChildFaces(face)[ptexFace.subFace];
    level = 1;
  }
  static const int kQuadrantChild[2][2] = {{0, 3}, {1, 2}};  // [u bit][v bit]
  for (; level < depth; ++level) {
    int shift = depth - level - 1;
    int child = kQuadrantChild[(param.GetU() >> shift) & 1][(param.GetV() >> shift) & 1];
    face = refiner.GetLevel(level).GetFaceChildFaces(face)[child];
  }
  if (face < 0) throwUnsupported("internal: an irregular patch does not match a refined face");
  endCaps_[depth][face] = domainOf(param, ptex_);
}

void PatchTopologyBuilder::addRing(int levelIndex, Index ev) {
  RingPiece ring;
  ring.layout = layoutRing(RefinedLevels{*out_.refiner_, levelOffsets_}, levelIndex, ev);
  ring.level = static_cast<uint8_t>(levelIndex);
  for (int i = 0; i < ring.layout.shape.sectors; ++i) {
    auto found = endCaps_[levelIndex].find(ring.layout.sectorFaces[i]);
    bool owned = found != endCaps_[levelIndex].end();
    ring.sectorOwned.push_back(owned ? 1 : 0);
    ring.sectorDomains.push_back(owned ? rotateToLattice(found->second, ring.layout.sectorRotations[i])
                                       : PatchDomain{});
  }
  out_.rings_.push_back(std::move(ring));
}

// Each end-cap face has exactly one irregular corner, its ring's EV. A ring owns the sectors
// whose faces are end caps; its other sectors are regular patches or holes, covered elsewhere.
void PatchTopologyBuilder::layOutRings() {
  for (int levelIndex = 0; levelIndex < int(endCaps_.size()); ++levelIndex) {
    const auto& level = out_.refiner_->GetLevel(levelIndex);
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
// patches and the rings of its end caps; pieces of the sheets' `holes` are dropped.
void PatchTopologyBuilder::refineAndLayOut(const ControlMesh& far, const std::vector<int>& holes, int isolation) {
  out_.refiner_ = createTopologyRefiner(far);
  const Far::PatchTableFactory::Options options = patchTableOptions(isolation);
  refineAdaptively(*out_.refiner_, options);
  checkpointNow();
  out_.refinedVertices_ = out_.refiner_->GetNumVerticesTotal();
  if (options_.afterRefining) options_.afterRefining(out_.refinedVertices_);
  const Far::TopologyRefiner& refiner = *out_.refiner_;
  std::unique_ptr<Far::PatchTable> table(Far::PatchTableFactory::Create(refiner, options));
  checkpointNow();

  levelOffsets_.assign(1, 0);
  for (int l = 0; l < refiner.GetMaxLevel(); ++l) {
    levelOffsets_.push_back(levelOffsets_.back() + refiner.GetLevel(l).GetNumVertices());
  }
  ptex_ = ptexFaces(refiner);
  endCaps_.assign(refiner.GetMaxLevel() + 1, {});
  std::vector<uint8_t> hole(far.faceCount(), 0);
  for (int f : holes) hole[f] = 1;

  RegularPatchLayout& regular = out_.regular_;
  for (int array = 0; array < table->GetNumPatchArrays(); ++array) {
    auto type = table->GetPatchArrayDescriptor(array).GetType();
    for (int p = 0; p < table->GetNumPatches(array); ++p) {
      auto cvs = table->GetPatchVertices(array, p);
      auto param = table->GetPatchParam(array, p);
      if (hole[ptex_[param.GetFaceId()].baseFace]) continue;
      if (type == Far::PatchDescriptor::REGULAR) {
        std::array<int, 16>& points = regular.points.emplace_back();
        for (int i = 0; i < 16; ++i) points[i] = cvs[i];
        regular.boundaryMasks.push_back(static_cast<uint8_t>(param.GetBoundary()));
        regular.domains.push_back(domainOf(param, ptex_));
        regular.levels.push_back(static_cast<uint8_t>(param.GetDepth()));
      } else if (type == Far::PatchDescriptor::QUADS) {
        addEndCap(param);
      } else {
        throwUnsupported("internal: unexpected OpenSubdiv patch type");
      }
    }
  }
  layOutRings();
}

void PatchTopologyBuilder::countRefinedFaces() {
  std::set<int> refinedBaseFaces;
  const RegularPatchLayout& regular = out_.regular_;
  for (size_t p = 0; p < regular.size(); ++p) {
    if (regular.levels[p] > 0) refinedBaseFaces.insert(regular.domains[p].baseFace);
  }
  for (const RingPiece& ring : out_.rings_) {
    for (size_t i = 0; i < ring.sectorDomains.size(); ++i) {
      if (ring.sectorOwned[i]) refinedBaseFaces.insert(ring.sectorDomains[i].baseFace);
    }
  }
  out_.stats_.locallyRefinedFaces = static_cast<int>(refinedBaseFaces.size());
}

void PatchTopologyBuilder::build() {
  checkpointNow();
  const RefinementInput input(mesh_);
  const ControlMesh& sheets = input.sheets();
  const int isolation = isolationLevelFor(sheets);
  if (options_.maxRefinedVertices > 0 || options_.beforeRefining) {
    // Without a limit the estimate is still wanted: one far beyond any machine's memory.
    const int64_t limit = options_.maxRefinedVertices > 0 ? options_.maxRefinedVertices : int64_t(1) << 50;
    const int64_t estimate = requireRefinementWithin(input.unholed(), limit, options_.checkpoint);
    if (options_.beforeRefining) options_.beforeRefining(estimate);
  }
  try {
    refineAndLayOut(sheets, sheets.holes, isolation);
  } catch (const TesseraError& error) {
    if (sheets.holes.empty() || error.kind() != ErrorKind::kUnsupported) throw;
    // Far's sparse levels leave hole faces out: a ring beside a hole can lack its lattice, or see
    // a semi-sharp edge of the hole that Far stopped isolating. Refined again as if there were no
    // holes (a hole changes no refinement rule), with the holes' pieces dropped, every ring is
    // complete and isolated. Not the first choice: the refined hole faces also split their
    // neighbours' patches (catmark_hole_test1 at 1e-3: 29 % more triangles).
    out_.regular_ = {};
    out_.rings_.clear();
    refineAndLayOut(input.unholed(), sheets.holes, isolation);
  }

  out_.inputVertices_ = mesh_.vertexCount();
  out_.inputFaces_ = mesh_.faceCount();
  out_.inputFaceVertices_ = static_cast<int>(mesh_.faceVertices.size());
  const ManifoldSheets& cut = input.cut();
  if (cut.cut()) out_.sheetVertex_ = cut.inputVertex;
  out_.sheetFaces_ = withoutPositions(sheets);
  out_.seamFaces_ = withoutPositions(cut.seamsOf(mesh_));
  out_.stats_.isolationLevel = isolation;
  out_.stats_.holes = static_cast<int>(mesh_.holes.size());
  out_.stats_.nonManifoldEdges = cut.nonManifoldEdges;
  out_.stats_.nonManifoldVertices = cut.nonManifoldVertices;
  countRefinedFaces();
}

PatchTopology::PatchTopology(const ControlMesh& mesh, const PreprocessingOptions& options) {
  PatchTopologyBuilder(*this, mesh, options).build();
}

PatchTopology::~PatchTopology() = default;

bool PatchTopology::fits(const ControlMesh& mesh) const {
  return mesh.vertexCount() == inputVertices_ && mesh.faceCount() == inputFaces_ &&
         int(mesh.faceVertices.size()) == inputFaceVertices_;
}

std::vector<Vec3> PatchTopology::sheetPositions(const ControlMesh& mesh) const {
  if (sheetVertex_.empty()) return mesh.positions;
  std::vector<Vec3> positions(sheetVertex_.size());
  for (size_t s = 0; s < sheetVertex_.size(); ++s) positions[s] = mesh.positions[size_t(sheetVertex_[s])];
  return positions;
}

void PatchTopology::releaseRefinement() {
  refiner_.reset();
  regular_ = {};
  rings_ = {};
}

size_t PatchTopology::bytes() const {
  // Far's levels: per refined vertex its faces, edges and tags, per face and edge their vertices
  // and neighbours, and the refinement's parent and child maps: ~350 bytes a refined vertex,
  // fitted so that the whole is at least what a kept topology holds resident (BM_Edit_Tessera's
  // kept_mib beside topology_charged_mib: 1.01-1.10 of it on six models).
  constexpr size_t kFarBytesPerVertex = 350;
  auto bytesOf = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  size_t rings = rings_.capacity() * sizeof(RingPiece);
  for (const RingPiece& ring : rings_) {
    rings += bytesOf(ring.layout.points) + bytesOf(ring.layout.sharpSpokes) + bytesOf(ring.layout.sectorFaces) +
             bytesOf(ring.layout.sectorRotations) + bytesOf(ring.sectorDomains) + bytesOf(ring.sectorOwned);
  }
  auto facesBytes = [&](const ControlMesh& m) {
    return bytesOf(m.faceSizes) + bytesOf(m.faceVertices) + bytesOf(m.creases) + bytesOf(m.corners) + bytesOf(m.holes);
  };
  return sizeof(PatchTopology) + size_t(refinedVertices()) * kFarBytesPerVertex + bytesOf(regular_.points) +
         bytesOf(regular_.boundaryMasks) + bytesOf(regular_.domains) + bytesOf(regular_.levels) + rings +
         bytesOf(sheetVertex_) + facesBytes(sheetFaces_) + facesBytes(seamFaces_);
}

namespace {

template <typename T>
void appendBytes(std::string& out, const std::vector<T>& values) {
  const uint64_t count = values.size();
  out.append(reinterpret_cast<const char*>(&count), sizeof(count));
  out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

}  // namespace

std::string topologySha256(const ControlMesh& mesh) {
  // Each array with its length, so that no two meshes' fields run into the same bytes; the
  // positions' count, since a vertex no face uses still numbers the rest; the UV values' count,
  // which Far's face-varying channel has.
  std::string bytes;
  const uint64_t vertices = mesh.positions.size();
  bytes.append(reinterpret_cast<const char*>(&vertices), sizeof(vertices));
  appendBytes(bytes, mesh.faceSizes);
  appendBytes(bytes, mesh.faceVertices);
  static_assert(sizeof(CreaseEdge) == 12 && sizeof(CornerVertex) == 8, "tags hashed as their bytes, no padding");
  appendBytes(bytes, mesh.creases);
  appendBytes(bytes, mesh.corners);
  appendBytes(bytes, mesh.holes);
  const SubdivisionRules& r = mesh.rules;
  bytes.append({char(r.boundary), char(r.creaseMethod), char(r.triangleSubdivision), char(r.uvInterpolation)});
  appendBytes(bytes, mesh.uvIndices);
  const uint64_t uvValues = mesh.uvs.size();
  bytes.append(reinterpret_cast<const char*>(&uvValues), sizeof(uvValues));
  return sha256Hex(bytes);
}

}  // namespace tessera
