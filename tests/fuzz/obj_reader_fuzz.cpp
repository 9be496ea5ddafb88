// libFuzzer entry point for the OBJ reader: every input must either read as a mesh or be refused
// with a TesseraError. Any other exception escapes and any sanitizer report aborts, and libFuzzer
// reports both as findings.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/base/error.h"
#include "core/mesh/manifold_sheets.h"
#include "core/mesh/obj_reader.h"

namespace {

// Messages go into gRPC statuses, which must be UTF-8: the reader escapes whatever it quotes.
bool isPrintableAscii(std::string_view message) {
  for (char c : message) {
    if (c < 0x20 || c > 0x7e) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const tessera::ControlMesh mesh = tessera::readObj(text, "fuzz.obj");
    tessera::validateControlMesh(mesh);  // what readObj returns must stay valid
    tessera::cutIntoSheets(mesh);
  } catch (const tessera::TesseraError& error) {
    if (!isPrintableAscii(error.what())) __builtin_trap();
  }
  return 0;
}
