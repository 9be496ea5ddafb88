// glTF 2.0 binary (GLB) output: one mesh, one primitive of indexed triangles with positions and
// normals, accessor bounds set, and the generator named in the asset. Written directly (the JSON
// through nlohmann::json, the binary chunk copied once); read back through tinygltf.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/watertight_tessellator.h"

namespace tessera {

std::vector<uint8_t> writeGlb(const TriangleMesh& mesh, const std::string& meshName);

// Reads back positions, normals and indices of a GLB written by writeGlb (for tests and tools).
// Throws TesseraError on anything it does not understand.
TriangleMesh readGlb(const std::vector<uint8_t>& bytes);

}  // namespace tessera
