#include "reference/models.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace tessera::testing {

std::string modelsDir() {
  const char* fromEnvironment = std::getenv("TESSERA_MODELS_DIR");
  return fromEnvironment != nullptr ? fromEnvironment : TESSERA_MODELS_DIR;
}

std::vector<std::string> benchmarkCharacters() {
  std::vector<std::string> paths;
  for (const char* name : {"bigguy", "monsterfrog", "armorguy", "t-rex", "car"}) {
    paths.push_back(modelsDir() + "/" + name + ".obj");
  }
  return paths;
}

std::vector<std::string> openSubdivShapes() {
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::directory_iterator(modelsDir() + "/opensubdiv-shapes")) {
    if (entry.path().extension() == ".obj") paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

std::string baseName(const std::string& path) { return std::filesystem::path(path).stem().string(); }

}  // namespace tessera::testing
