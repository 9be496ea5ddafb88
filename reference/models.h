// Where the shared test meshes live, and which of them Tessera supports.
#pragma once

#include <string>
#include <vector>

namespace tessera::testing {

std::string modelsDir();  // TESSERA_MODELS_DIR env var, else the build-time default
std::vector<std::string> benchmarkCharacters();  // the paper's five models, full paths
std::vector<std::string> openSubdivShapes();     // every catmark_*.obj, full paths, sorted
std::string baseName(const std::string& path);   // "catmark_cube" for ".../catmark_cube.obj"

}  // namespace tessera::testing
