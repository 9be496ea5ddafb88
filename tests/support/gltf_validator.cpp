#include "tests/support/gltf_validator.h"

#include <cstdio>
#include <fstream>

namespace tessera::testing {

bool ValidatorReport::clean() const {
  return ran && report.find("\"numErrors\":0,") != std::string::npos &&
         report.find("\"numWarnings\":0,") != std::string::npos;
}

ValidatorReport validateGlb(const std::vector<uint8_t>& glb, const std::string& name) {
  std::string file = std::string(TESSERA_BINARY_DIR) + "/validate-" + name + ".glb";
  std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(glb.data()), glb.size());
  std::string command = "node " + std::string(TESSERA_SOURCE_DIR) + "/tests/gltf/validate.js " + file;
  ValidatorReport result;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  char chunk[4096];
  while (size_t n = fread(chunk, 1, sizeof chunk, pipe)) result.report.append(chunk, n);
  result.ran = pclose(pipe) == 0;
  return result;
}

}  // namespace tessera::testing
