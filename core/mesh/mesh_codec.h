// The canonical binary encoding of a control mesh: what the stores keep and what the sha256 in
// tessera.v1.Mesh covers (the layout is documented there, in mesh.proto). Fixed little-endian
// fields and no padding make it compact, portable between replicas and hashable.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "core/mesh/control_mesh.h"

namespace tessera {

// Thrown when stored bytes are not a valid encoding (corruption, or a foreign row).
class MeshDecodeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::string encodeCanonicalMesh(const ControlMesh& mesh);

// Never reads past bytes, whatever they contain; structural checks only (validateControlMesh ran
// before the mesh was stored).
ControlMesh decodeCanonicalMesh(std::string_view bytes);

// Approximate heap footprint of a decoded mesh, for cache budgets.
size_t meshHeapBytes(const ControlMesh& mesh);

}  // namespace tessera
