#include "core/pipeline/preprocessing.h"

#include "core/surface/adaptive_surface.h"
#include "core/topology/limit_uvs.h"
#include "core/surface/tolerance_model.h"

namespace tessera {

MeshTopology::MeshTopology(const ControlMesh& mesh, const PreprocessingOptions& options)
    : pieces(mesh, options), seams(pieces.seamFaces()) {
  if (!mesh.hasUvs()) return;
  uvValues = mesh.uvs;
  uvs = std::make_shared<const LimitUvs>(mesh);
}

size_t MeshTopology::bytes() const {
  return pieces.bytes() + seams.bytes() + uvValues.capacity() * sizeof(float) + (uvs ? uvs->bytes() : 0);
}

std::shared_ptr<const MeshTopology> buildMeshTopology(const ControlMesh& mesh, const PreprocessingOptions& options) {
  return std::make_shared<const MeshTopology>(mesh, options);
}

namespace {

// The patches and rings of `mesh` through its topology, which its positions are refined through.
PatchSet piecesThrough(const ControlMesh& mesh, const MeshTopology& topology, const PreprocessingOptions& options) {
  // What the patch set is made of grows with the refinement (memory_estimates.h), known here
  // whether the topology was built now or before.
  if (options.afterRefining) options.afterRefining(topology.pieces.refinedVertices());
  const bool sameUvs = topology.uvs && mesh.uvs == topology.uvValues;
  return reduceToPatches(mesh, topology.pieces, options.checkpoint, sameUvs ? topology.uvs : nullptr);
}

void addSurface(PatchSet& patches, const ControlMesh& mesh, const MeshTopology& topology,
                const PreprocessingOptions& options) {
  patches.adaptive = buildAdaptiveSurface(patches, topology.pieces.sheetFaces(), topology.seams, mesh.vertexCount(),
                                          options.checkpoint, chainFloorFor(options.finestRelativeTolerance));
}

}  // namespace

PatchSet buildPatchSet(const ControlMesh& mesh, const PreprocessingOptions& options) {
  validateControlMesh(mesh);
  MeshTopology topology(mesh, options);
  PatchSet patches = piecesThrough(mesh, topology, options);
  // Kept by no one, Far's levels go before the tree is built: the cold job's peak is one or the
  // other (the rook: ~360 MiB of refinement).
  topology.pieces.releaseRefinement();
  addSurface(patches, mesh, topology, options);
  return patches;
}

PatchSet buildPatchSet(const ControlMesh& mesh, const MeshTopology& topology, const PreprocessingOptions& options) {
  validateControlMesh(mesh);
  PatchSet patches = piecesThrough(mesh, topology, options);
  addSurface(patches, mesh, topology, options);
  return patches;
}

double finestRelativeTolerance(const ControlMesh& mesh, const TessellationOptions& options) {
  if (options.accuracy.uniform() || mesh.positions.empty()) return 0;
  Vec3 lo, hi;
  mesh.bounds(lo, hi);
  const double diagonal = length(Vec3d(hi) - Vec3d(lo));
  if (!(diagonal > 0)) return 0;
  // The surface is relative to the mesh's origin; a camera is in model units (tessellate.h).
  TessellationOptions relative = options;
  relative.encodingReserve = 0;
  if (relative.camera) {
    relative.camera->eye = relative.camera->eye - mesh.origin;
    relative.camera->target = relative.camera->target - mesh.origin;
  }
  const float boxLo[3] = {lo.x, lo.y, lo.z}, boxHi[3] = {hi.x, hi.y, hi.z};
  return ToleranceModel(relative, lo, hi).forBox(boxLo, boxHi) / diagonal;
}

}  // namespace tessera
