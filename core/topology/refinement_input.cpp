#include "core/topology/refinement_input.h"

namespace tessera {

RefinementInput::RefinementInput(const ControlMesh& mesh) : input_(mesh), cut_(cutIntoSheets(mesh)) {
  if (sheets().holes.empty()) return;
  unholed_ = sheets();
  unholed_.holes.clear();
}

}  // namespace tessera
