// The control mesh as a user hands it to Tessera: positions, faces of any size, and the
// subdivision tags and rules OpenSubdiv understands (creases, corners, holes; boundary, crease
// and triangle rules).
// Plain arrays in, so the OBJ reader, the gRPC upload and tests all build the same thing.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/vec3.h"

namespace tessera {

// Sharpness at or above this value is infinitely sharp, as in OpenSubdiv's Sdc
// (SHARPNESS_INFINITE).
inline constexpr float kInfiniteSharpness = 10.0f;

struct CreaseEdge {
  int v0 = 0, v1 = 0;
  float sharpness = 0.0f;
};

struct CornerVertex {
  int vertex = 0;
  float sharpness = 0.0f;
};

// Sdc's VtxBoundaryInterpolation: which boundary features are made sharp.
enum class BoundaryInterpolation : uint8_t {
  kEdgeOnly,       // boundary edges are infinitely sharp (OpenSubdiv's default)
  kEdgeAndCorner,  // ... and boundary vertices with a single face are corners
  kNone,           // no surface over faces at a boundary vertex: they only support their neighbours
};

// Sdc's CreasingMethod: how a semi-sharp edge's sharpness decays at each refinement.
enum class CreaseMethod : uint8_t {
  kUniform,  // sharpness − 1 per level (OpenSubdiv's default)
  kChaikin,  // Chaikin's rule: a child edge's sharpness averages its neighbours' along the crease
};

// Sdc's TriangleSubdivision: the weights at a triangle's vertices in the first refinement.
enum class TriangleSubdivision : uint8_t {
  kCatmark,  // Catmull-Clark's own weights (OpenSubdiv's default)
  kSmooth,   // Loop-like weights that round triangles off (TRI_SUB_SMOOTH)
};

// Sdc's FVarLinearInterpolation: where texture coordinates (face-varying data) follow the control
// polygon linearly instead of being smoothed as positions are. Listed with OpenSubdiv's default
// first, so encodings written before UVs were accepted read back as it.
enum class UvInterpolation : uint8_t {
  kAll,           // linear everywhere (FVAR_LINEAR_ALL, OpenSubdiv's default)
  kNone,          // smooth everywhere, boundaries included (FVAR_LINEAR_NONE)
  kCornersOnly,   // smooth, with UV-boundary corners kept (FVAR_LINEAR_CORNERS_ONLY)
  kCornersPlus1,  // ... and junctions of 3+ UV regions (FVAR_LINEAR_CORNERS_PLUS1)
  kCornersPlus2,  // ... and concave corners (FVAR_LINEAR_CORNERS_PLUS2)
  kBoundaries,    // linear along UV boundaries (FVAR_LINEAR_BOUNDARIES)
};

// The Sdc options a mesh carries besides its tags (OpenSubdiv's defaults unless the source says).
struct SubdivisionRules {
  BoundaryInterpolation boundary = BoundaryInterpolation::kEdgeOnly;
  CreaseMethod creaseMethod = CreaseMethod::kUniform;
  TriangleSubdivision triangleSubdivision = TriangleSubdivision::kCatmark;
  UvInterpolation uvInterpolation = UvInterpolation::kAll;
  friend bool operator==(const SubdivisionRules&, const SubdivisionRules&) = default;
};

struct ControlMesh {
  std::vector<Vec3> positions;
  std::vector<int> faceSizes;     // one entry per face, each >= 3
  std::vector<int> faceVertices;  // concatenated vertex indices, counter-clockwise per face
  std::vector<CreaseEdge> creases;
  std::vector<CornerVertex> corners;
  std::vector<int> holes;  // face indices that are holes (not part of the surface)
  SubdivisionRules rules;
  // Texture coordinates, face-varying as OBJ's vt: (u, v) pairs, and per face corner (in the
  // order of faceVertices) the index of its pair. Both empty when the mesh has none.
  std::vector<float> uvs;
  std::vector<int> uvIndices;
  // The point positions are relative to (model units). Zero unless the mesh lies far from the
  // origin for its size, where float positions would round its detail away: the OBJ reader then
  // puts it at the centre of the mesh's box (docs/FAR-FROM-ORIGIN.md).
  Vec3d origin{0, 0, 0};

  bool hasUvs() const { return !uvIndices.empty(); }
  bool hasOrigin() const { return origin.x != 0 || origin.y != 0 || origin.z != 0; }
  int vertexCount() const { return static_cast<int>(positions.size()); }
  int faceCount() const { return static_cast<int>(faceSizes.size()); }
  // The box of the control points (relative to `origin`; a point at the origin when there are
  // none), which holds the limit surface: Catmull-Clark's masks are convex combinations.
  void bounds(Vec3& lo, Vec3& hi) const {
    lo = hi = positions.empty() ? Vec3() : positions[0];
    for (const Vec3& p : positions) {
      lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
      hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
    }
  }
};

// Size limits a mesh must respect; the server can lower them per deployment.
struct MeshLimits {
  int64_t maxVertices = 50'000'000;
  int64_t maxFaces = 50'000'000;
  int maxFaceSize = 64;
  int maxValence = 65535;  // faces at one vertex: OpenSubdiv's topology holds at most 65535
  float maxAbsCoordinate = 1e18f;
};

// Checks every invariant the rest of core/ relies on; throws TesseraError naming the first
// problem and where it is (face, vertex, crease index). Never crashes on any input.
void validateControlMesh(const ControlMesh& mesh, const MeshLimits& limits = {});

}  // namespace tessera
