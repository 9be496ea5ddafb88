// Watertight triangulation of a tessellation plan (MATH.md §5; the paper leaves it to future
// work). Every piece edge is split where its neighbours' edges end (FAS and Far level changes
// give T-junctions), each elementary interval gets one level (the finest its pieces ask for)
// and its vertices are computed once and shared, so every shared edge has bit-identical
// vertices. Each piece's N×N interior grid is stitched to its boundary polylines.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/uniform/domain_keys.h"
#include "core/uniform/tessellation_plan.h"

namespace tessera {

struct TriangleMesh {
  std::vector<Vec3> positions;  // relative to `origin`
  std::vector<Vec3> normals;
  std::vector<uint32_t> indices;  // counter-clockwise seen from the normal side
  Vec3d origin{0, 0, 0};          // the control mesh's (ControlMesh::origin)
  std::vector<float> uvs;         // u, v per vertex when the control mesh has UVs (core/output/uv_seams.h)
  // Where each vertex lies in the limit surface's parameterization (base face, quad sub-face or
  // -1, u, v): lets tests compare every vertex and triangle with an exact evaluator.
  std::vector<int> vertexFace, vertexSubFace;
  std::vector<double> vertexUv;  // u, v per vertex
  // The vertex whose position each vertex repeats bit for bit with a normal of its own (adaptive
  // path: the other side of a crease or of a fold narrower than ε) or a UV of its own (any path:
  // the other side of a UV seam), itself otherwise; empty when no vertex is a copy (uniform path). The adaptive
  // path fills these per-vertex records and trianglePiece only with recordParameters.
  std::vector<uint32_t> vertexPoint;
  std::vector<uint32_t> trianglePiece;  // the plan piece (adaptive: the tile) each triangle belongs to
  // With recordParameters: (s, t) of each corner in its piece; on the adaptive path (u, v) in the
  // root (base face, quad sub-face or -1) that triangleFace, triangleSubFace name.
  std::vector<double> triangleST;
  std::vector<int> triangleFace, triangleSubFace;

  size_t triangleCount() const { return indices.size() / 3; }
};

// Triangle count the plan will produce, before building anything (for budgets).
int64_t estimateTriangles(const TessellationPlan& plan);

TriangleMesh tessellatePlan(const TessellationPlan& plan, const FaceTopology& faces,
                           bool recordParameters = false,
                           const std::function<void()>& checkpoint = {});

}  // namespace tessera
