#include "core/topology/far_topology.h"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <cmath>

#include "core/base/error.h"

namespace tessera {

namespace {

namespace Sdc = OpenSubdiv::Sdc;

// Far's primvar interpolation works on any type with Clear and AddWithWeight.
struct RefinedPoint {
  Vec3d p;
  void Clear() { p = Vec3d(); }
  void AddWithWeight(const RefinedPoint& src, double weight) { p += src.p * weight; }
};

Sdc::Options::VtxBoundaryInterpolation sdcBoundary(BoundaryInterpolation boundary) {
  switch (boundary) {
    case BoundaryInterpolation::kEdgeOnly:
      return Sdc::Options::VTX_BOUNDARY_EDGE_ONLY;
    case BoundaryInterpolation::kEdgeAndCorner:
      return Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER;
    case BoundaryInterpolation::kNone:
      return Sdc::Options::VTX_BOUNDARY_NONE;
  }
  return Sdc::Options::VTX_BOUNDARY_EDGE_ONLY;
}

Sdc::Options::FVarLinearInterpolation sdcUvInterpolation(UvInterpolation rule) {
  switch (rule) {
    case UvInterpolation::kNone: return Sdc::Options::FVAR_LINEAR_NONE;
    case UvInterpolation::kCornersOnly: return Sdc::Options::FVAR_LINEAR_CORNERS_ONLY;
    case UvInterpolation::kCornersPlus1: return Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1;
    case UvInterpolation::kCornersPlus2: return Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2;
    case UvInterpolation::kBoundaries: return Sdc::Options::FVAR_LINEAR_BOUNDARIES;
    case UvInterpolation::kAll: break;
  }
  return Sdc::Options::FVAR_LINEAR_ALL;
}

// The mesh's rules, as Far and Bfr read them. Chaikin's rule and smooth triangles act only in
// Far's refinement (docs/ADAPTIVE.md §9); VTX_BOUNDARY_NONE makes Far tag the faces at a
// boundary vertex as holes.
Sdc::Options subdivisionOptions(const ControlMesh& mesh) {
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(sdcBoundary(mesh.rules.boundary));
  options.SetFVarLinearInterpolation(sdcUvInterpolation(mesh.rules.uvInterpolation));
  options.SetCreasingMethod(mesh.rules.creaseMethod == CreaseMethod::kChaikin
                                ? Sdc::Options::CREASE_CHAIKIN
                                : Sdc::Options::CREASE_UNIFORM);
  options.SetTriangleSubdivision(mesh.rules.triangleSubdivision == TriangleSubdivision::kSmooth
                                     ? Sdc::Options::TRI_SUB_SMOOTH
                                     : Sdc::Options::TRI_SUB_CATMARK);
  return options;
}

}  // namespace

std::unique_ptr<Far::TopologyRefiner> createTopologyRefiner(const ControlMesh& mesh, bool withUvs) {
  std::vector<int> creasePairs;
  std::vector<float> creaseWeights;
  for (const CreaseEdge& crease : mesh.creases) {
    creasePairs.push_back(crease.v0);
    creasePairs.push_back(crease.v1);
    creaseWeights.push_back(crease.sharpness);
  }
  std::vector<int> cornerVertices;
  std::vector<float> cornerWeights;
  for (const CornerVertex& corner : mesh.corners) {
    cornerVertices.push_back(corner.vertex);
    cornerWeights.push_back(corner.sharpness);
  }

  Far::TopologyDescriptor descriptor;
  descriptor.numVertices = mesh.vertexCount();
  descriptor.numFaces = mesh.faceCount();
  descriptor.numVertsPerFace = mesh.faceSizes.data();
  descriptor.vertIndicesPerFace = mesh.faceVertices.data();
  descriptor.numCreases = static_cast<int>(mesh.creases.size());
  descriptor.creaseVertexIndexPairs = creasePairs.data();
  descriptor.creaseWeights = creaseWeights.data();
  descriptor.numCorners = static_cast<int>(mesh.corners.size());
  descriptor.cornerVertexIndices = cornerVertices.data();
  descriptor.cornerWeights = cornerWeights.data();
  descriptor.numHoles = static_cast<int>(mesh.holes.size());
  descriptor.holeIndices = mesh.holes.data();
  Far::TopologyDescriptor::FVarChannel uvChannel;
  if (withUvs && mesh.hasUvs()) {
    uvChannel.numValues = int(mesh.uvs.size() / 2);
    uvChannel.valueIndices = mesh.uvIndices.data();
    descriptor.numFVarChannels = 1;
    descriptor.fvarChannels = &uvChannel;
  }

  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  Factory::Options options(Sdc::SCHEME_CATMARK, subdivisionOptions(mesh));
  options.validateFullTopology = false;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(descriptor, options));
  if (!refiner) throwInvalid("OpenSubdiv could not build the topology of the mesh");
  return refiner;
}

std::vector<Vec3d> refinedPositions(const Far::TopologyRefiner& refiner,
                                    const std::vector<Vec3>& basePositions) {
  std::vector<RefinedPoint> points(refiner.GetNumVerticesTotal());
  for (size_t v = 0; v < basePositions.size(); ++v) points[v].p = Vec3d(basePositions[v]);
  Far::PrimvarRefinerReal<double> primvarRefiner(refiner);
  RefinedPoint* source = points.data();
  for (int level = 1; level <= refiner.GetMaxLevel(); ++level) {
    RefinedPoint* destination = source + refiner.GetLevel(level - 1).GetNumVertices();
    primvarRefiner.Interpolate(level, source, destination);
    source = destination;
  }
  std::vector<Vec3d> result(points.size());
  for (size_t i = 0; i < points.size(); ++i) result[i] = points[i].p;
  return result;
}

float maxSemiSharpness(const ControlMesh& mesh) {
  float result = 0.0f;
  for (const CreaseEdge& c : mesh.creases) {
    if (c.sharpness < kInfiniteSharpness) result = std::max(result, c.sharpness);
  }
  for (const CornerVertex& c : mesh.corners) {
    if (c.sharpness < kInfiniteSharpness) result = std::max(result, c.sharpness);
  }
  return result;
}

int isolationLevelFor(const ControlMesh& mesh) {
  int level = std::max(2, int(std::ceil(maxSemiSharpness(mesh))) + 1);
  return std::min(level, 10);
}

Far::PatchTableFactory::Options patchTableOptions(int isolation) {
  Far::PatchTableFactory::Options options(isolation);
  options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_BILINEAR_BASIS);
  options.useInfSharpPatch = true;
  options.useSingleCreasePatch = false;
  options.generateLegacySharpCornerPatches = false;
  options.generateVaryingTables = false;
  return options;
}

void refineAdaptively(Far::TopologyRefiner& refiner,
                      const Far::PatchTableFactory::Options& options) {
  auto adaptive = options.GetRefineAdaptiveOptions();
  adaptive.SetSecondaryLevel(2);
  refiner.RefineAdaptive(adaptive);
}

}  // namespace tessera
