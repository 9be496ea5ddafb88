// Synthetic meshes made of one extraordinary ring, with vertex i = CER point i, for comparing
// FAS against OpenSubdiv's refinement of the very same mesh.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/rings/cer_layout.h"

namespace tessera::testing {

// A ring of `shape` whose points are the lattice mapped around the EV with random jitter
// (deterministic for a seed). `sharpSpokes` (spokeCount entries) become infinitely sharp creases
// along both spoke edges; `cornerEv` tags the EV as an infinitely sharp corner.
ControlMesh makeRingMesh(const cer::RingShape& shape, uint32_t seed,
                         const std::vector<uint8_t>& sharpSpokes = {}, bool cornerEv = false);

// The 4n quads of a ring in CER vertex numbering.
std::vector<int> ringFaceVertices(const cer::RingShape& shape);

}  // namespace tessera::testing
