// Two tessellations that must be the same bit for bit (a second code path, another thread count):
// the first array in which they differ, named, so that a test failure says where.
#pragma once

#include <string>

#include "core/mesh/triangle_mesh.h"

namespace tessera::testing {

// "" when every array of the two meshes (positions, normals, indices, UVs, origin and the
// recorded parameters) holds the same bits; else the first one that does not.
std::string meshDifference(const TriangleMesh& a, const TriangleMesh& b);

}  // namespace tessera::testing
