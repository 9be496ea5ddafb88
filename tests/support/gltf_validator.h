// Runs Khronos glTF-Validator (npm gltf-validator, installed in tests/gltf by tools/test.sh) on a
// GLB and returns its JSON report.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tessera::testing {

struct ValidatorReport {
  bool ran = false;  // false: node or the validator could not be run (report says why)
  std::string report;
  bool clean() const;  // zero errors and zero warnings
};

// Writes the GLB as TESSERA_BINARY_DIR/validate-NAME.glb and validates that file.
ValidatorReport validateGlb(const std::vector<uint8_t>& glb, const std::string& name);

}  // namespace tessera::testing
