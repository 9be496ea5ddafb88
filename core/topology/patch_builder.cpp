// Preprocessing's positions (paper §3.2): every refined vertex from the mesh's points through
// Far's levels (the topology's refinement), then each regular patch's net and each ring's points
// gathered from them as the topology lays them out.
#include "core/topology/patch_builder.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/base/error.h"
#include "core/topology/far_topology.h"
#include "core/topology/limit_uvs.h"

namespace tessera {

namespace {

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

constexpr size_t kPiecesPerCheckpoint = 4096;

RegularPatches gatherRegular(const RegularPatchLayout& layout, const std::vector<Vec3d>& positions,
                             const std::function<void()>& checkpoint) {
  RegularPatches regular;
  regular.bspline.resize(layout.size());
  // On every core, a checkpoint a block: the rook's 425K nets took 68 ms on one.
  const size_t blocks = (layout.size() + kPiecesPerCheckpoint - 1) / kPiecesPerCheckpoint;
  tbb::parallel_for(size_t(0), blocks, [&](size_t block) {
    if (checkpoint) checkpoint();
    const size_t end = std::min(layout.size(), (block + 1) * kPiecesPerCheckpoint);
    for (size_t p = block * kPiecesPerCheckpoint; p < end; ++p) {
      ControlNet& net = regular.bspline[p];
      for (int i = 0; i < 16; ++i) net[i] = Vec3(positions[size_t(layout.points[p][i])]);
      fillPhantoms(net, layout.boundaryMasks[p]);
    }
  });
  regular.domains = layout.domains;
  regular.levels = layout.levels;
  return regular;
}

void addRing(RingSet& rings, const RingPiece& piece, const std::vector<Vec3d>& positions) {
  const RingLayout& layout = piece.layout;
  const std::vector<Vec3d> points = ringPoints(layout, positions);
  const Vec3d center = points[0];
  rings.shapes.push_back(layout.shape);
  rings.cornerEv.push_back(layout.cornerEv ? 1 : 0);
  rings.levels.push_back(piece.level);
  rings.pointOffsets.push_back(static_cast<int>(rings.points.size() / 3));
  for (const Vec3d& point : points) {
    Vec3d p = point - center;
    rings.points.insert(rings.points.end(), {float(p.x), float(p.y), float(p.z)});
  }
  rings.centers.push_back(Vec3(center));
  rings.spokeOffsets.push_back(static_cast<int>(rings.sharpSpokes.size()));
  rings.sharpSpokes.insert(rings.sharpSpokes.end(), layout.sharpSpokes.begin(), layout.sharpSpokes.end());
  rings.sectorOffsets.push_back(static_cast<int>(rings.sectorDomains.size()));
  rings.sectorOwned.insert(rings.sectorOwned.end(), piece.sectorOwned.begin(), piece.sectorOwned.end());
  rings.sectorDomains.insert(rings.sectorDomains.end(), piece.sectorDomains.begin(), piece.sectorDomains.end());
}

}  // namespace

PatchSet reduceToPatches(const ControlMesh& mesh, const PatchTopology& topology,
                         const std::function<void()>& checkpoint, std::shared_ptr<const LimitUvs> uvs) {
  if (!topology.fits(mesh)) {
    throwInvalid("the mesh has " + std::to_string(mesh.vertexCount()) + " vertices and " +
                 std::to_string(mesh.faceCount()) + " faces, not the topology it was matched with");
  }
  if (!topology.holdsRefinement()) throw std::logic_error("reduceToPatches: the topology's refinement was released");
  const std::vector<Vec3d> positions = refinedPositions(topology.refiner(), topology.sheetPositions(mesh));
  if (checkpoint) checkpoint();
  PatchSet result;
  result.regular = gatherRegular(topology.regular(), positions, checkpoint);
  for (const RingPiece& piece : topology.rings()) {
    if (checkpoint && result.rings.size() % kPiecesPerCheckpoint == 0) checkpoint();
    addRing(result.rings, piece, positions);
  }
  result.stats = topology.stats();
  mesh.bounds(result.boundsMin, result.boundsMax);
  if (mesh.hasUvs()) result.uvs = uvs ? std::move(uvs) : std::make_shared<const LimitUvs>(mesh);
  return result;
}

}  // namespace tessera
