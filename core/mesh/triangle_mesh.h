// The output of every tessellation path (uniform and adaptive) and the input of every writer
// (GLB, UV seams): indexed triangles with normals, and what tests need to check each vertex and
// triangle against an exact evaluator.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/vec3.h"

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

}  // namespace tessera
