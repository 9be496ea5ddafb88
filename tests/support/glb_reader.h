// A GLB read back as a viewer sees it, through tinygltf (the glTF library docs/GLB.md names) and,
// for EXT_meshopt_compression, which tinygltf leaves to the application, meshoptimizer's decoders:
// what the tests measure against the limit surface.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh/triangle_mesh.h"

namespace tessera::testing {

// Positions (through the node's translation and scale, in float as a viewer computes them),
// normals, UVs and indices of a GLB writeGlb wrote, in any encoding. Throws TesseraError
// (kInvalidInput) on anything it cannot trust.
TriangleMesh readGlb(const std::vector<uint8_t>& bytes);

}  // namespace tessera::testing
