// OpenSubdiv Bfr::Tessellation at one uniform rate on every face, assembled into one watertight
// indexed triangle mesh: the "oracle uniform rate" tessellation that Tessera's adaptive one is
// compared with. At a uniform rate both faces of an edge place the same R - 1 points on it
// (Bfr tutorial 3.x), so corners and edge points are named by base vertex and base edge and
// evaluated once, by the lowest-numbered face that has them; interior points belong to their face.
// Facets are Bfr's triangles (quads split in two, n-gons as Bfr triangulates its quad sub-faces).
// Positions are the LimitSurface's (Bfr at approximation level 6, or Far), so mesh vertices lie on
// the reference surface.
//
// Every triangle records where it lies: its face and (for n-gons) one normalized sub-face, with
// the corners' (u, v) in that sub-face. Bfr's n-gon facets straddle sub-faces (near the spokes at
// most rates): corners in the next or previous sub-face are unfolded into the chosen one as if the
// face were a quad ((s, t) -> (2 - t, s) and (t, 2 - s), the inverse of
// LimitSurface::continueDomain, which measureLimitDistance applies to every sample's parametric
// seed); the face centre is (1, 1) in every sub-face. Corners in other sub-faces (only at rate 1)
// are put at the centre: a poor seed, which the kd-tree's seeds make up for.
#pragma once

#include <cstdint>
#include <vector>

#include "reference/limit_distance.h"
#include "reference/limit_surface.h"

namespace tessera::testing {

struct UniformTessellation {
  std::vector<Vec3> positions;
  std::vector<uint32_t> indices;  // three per triangle, counter-clockwise as the control faces
  std::vector<int> triangleFace, triangleSubFace;
  std::vector<double> cornerUv;  // six per triangle

  size_t triangleCount() const { return indices.size() / 3; }
  TriangleMeshView view() const;
};

// Throws std::invalid_argument for a rate below 1.
UniformTessellation tessellateUniform(const LimitSurface& surface, int rate);

// The number of triangles tessellateUniform would make, without making them (for budgets).
size_t uniformTriangleCount(const LimitSurface& surface, int rate);

}  // namespace tessera::testing
