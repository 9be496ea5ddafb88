// What OpenSubdiv refines for a control mesh (docs/NONMANIFOLD.md, docs/DECISIONS.md "Holes
// refined where a ring needs them"): its manifold sheets, and where Far's sparse levels leave a
// ring beside a hole without its lattice (they leave hole faces out), the sheets with their hole
// tags cleared: a hole changes no refinement rule, only which faces have a surface, and the
// holes' pieces are dropped afterwards. The upload bounds the larger refinement.
#pragma once

#include "core/mesh/control_mesh.h"
#include "core/mesh/manifold_sheets.h"

namespace tessera {

class RefinementInput {
 public:
  // Throws as cutIntoSheets does. Copies the mesh only where the refined form differs from it.
  explicit RefinementInput(const ControlMesh& mesh);
  RefinementInput(const RefinementInput&) = delete;
  RefinementInput& operator=(const RefinementInput&) = delete;

  const ManifoldSheets& cut() const { return cut_; }
  // The sheets, holes included (the faces that have a surface).
  const ControlMesh& sheets() const { return cut_.sheetsOf(input_); }
  // The sheets without hole tags: what Far refines where the sheets' own refinement leaves a
  // ring beside a hole without its lattice, and the most it refines.
  const ControlMesh& unholed() const { return unholed_.faceSizes.empty() ? sheets() : unholed_; }

 private:
  const ControlMesh& input_;
  ManifoldSheets cut_;
  ControlMesh unholed_;  // empty unless the sheets have holes
};

}  // namespace tessera
