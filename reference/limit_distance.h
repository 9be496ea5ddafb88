// The measured two-sided distance between a triangle mesh and the exact Catmull-Clark limit
// surface of its control mesh (LimitSurface: Bfr at approximation level 6, or Far for interior
// valence 2), for comparing tessellations with an oracle and for tests that must be able to fail.
//
//  - mesh -> limit: every triangle is sampled at the barycentric points (i, j, k)/K, i + j + k = K,
//    corners excluded; each sample is projected onto the limit surface by Gauss-Newton inside a
//    face domain (reference/limit_projection.h) from several seeds, the triangle's own
//    parametric point when its parameters agree and the nearest limit samples of a kd-tree in up
//    to `spatialSeeds` domains (and from every domain for a sample those leave farther than
//    `everyDomainBeyond`); its distance is the smallest reached. The maximum over samples.
//  - limit -> mesh: every domain is sampled on an S×S grid, border included; each sample's
//    distance to the mesh is exact (an AABB tree and the point-triangle distance). The maximum.
//
// The mesh -> limit side is computed lazily but exactly: a first pass projects every sample from
// one seed only, which bounds its distance from above; the full set of seeds is then tried on
// triangles in decreasing order of that bound until the bound is no larger than the maximum found.
// Both maxima are lower bounds of the true one-sided Hausdorff distances (they are maxima over
// samples); with parameters the parametric seed makes the mesh -> limit projection reliable.
#pragma once

#include <cstdint>
#include <limits>
#include <span>

#include "core/mesh/triangle_mesh.h"
#include "reference/limit_surface.h"

namespace tessera::testing {

// A triangle mesh to measure, as views of plain arrays (nothing is copied, nothing owned).
struct TriangleMeshView {
  std::span<const Vec3> positions;
  std::span<const uint32_t> indices;  // three per triangle
  // Optional: where each vertex lies on the limit surface (face, sub-face or -1, u, v), as in
  // TriangleMesh. A vertex shared by two faces carries only one of them, so a triangle gets a
  // parametric seed from these only when its three vertices name the same (face, sub-face).
  std::span<const int> vertexFace, vertexSubFace;
  std::span<const double> vertexUv;  // two per vertex
  // Optional, preferred when present: one (face, sub-face) per triangle and (u, v) per corner in
  // that domain (may lie outside [0,1]^2; samples are clamped), for meshes whose triangles meet
  // at vertices of several domains (the border of a face's tessellation).
  std::span<const int> triangleFace, triangleSubFace;
  std::span<const double> cornerUv;  // six per triangle

  size_t triangleCount() const { return indices.size() / 3; }
};

// The positions, indices and parameters of a core TriangleMesh: per triangle when it recorded
// them (TessellationOptions::recordParameters), else per vertex.
TriangleMeshView viewOf(const TriangleMesh& mesh);

struct LimitDistanceOptions {
  int triangleSamples = 4;  // K >= 2: barycentric sample points per triangle side
  int limitSamples = 16;    // S >= 2: samples per domain side, border included
  int seedSamples = 8;      // the kd-tree's limit samples per domain side (cell centres)
  int spatialSeeds = 6;     // domains (1..16) tried from the kd-tree for each mesh sample
  // A mesh sample whose nearest limit point from those seeds is farther than this (object units)
  // is projected again from every domain, each from its sample nearest to it: the seeds can all
  // lie on other sheets where the surface folds back within a few samples' spacing.
  double everyDomainBeyond = std::numeric_limits<double>::infinity();
};

struct SurfaceLocation {
  int face = -1, subFace = -1;
  double u = 0, v = 0;
};

struct LimitDistanceReport {
  double meshToLimit = 0;            // max over mesh samples of the distance to the limit surface
  double limitToMesh = 0;            // max over limit samples of the distance to the mesh
  double diagonal = 0;               // of the control points' bounding box
  SurfaceLocation meshToLimitAt;     // the limit point nearest to the worst mesh sample
  uint32_t meshToLimitTriangle = 0;  // the triangle holding that sample
  SurfaceLocation limitToMeshAt;     // the worst limit sample
  size_t meshSamples = 0, limitSamples = 0;
  size_t trianglesReprojected = 0;  // triangles the full set of seeds was tried on

  double twoSided() const { return meshToLimit > limitToMesh ? meshToLimit : limitToMesh; }
  const SurfaceLocation& twoSidedAt() const {
    return meshToLimit > limitToMesh ? meshToLimitAt : limitToMeshAt;
  }
  double meshToLimitRelative() const { return meshToLimit / diagonal; }
  double limitToMeshRelative() const { return limitToMesh / diagonal; }
  double twoSidedRelative() const { return twoSided() / diagonal; }
};

// Parallel (TBB). Throws std::invalid_argument for bad options or parameter arrays of the wrong
// size.
LimitDistanceReport measureLimitDistance(const LimitSurface& surface, const TriangleMeshView& mesh,
                                         const LimitDistanceOptions& options = {});

}  // namespace tessera::testing
