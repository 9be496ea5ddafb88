// Preprocessing's reduction (paper §3.2, docs/DECISIONS.md "Preprocessing"): a control mesh,
// through its topology's refinement and layout (core/topology/patch_topology.h), to its regular
// B-spline patches and extraordinary rings in CER (core/rings/patch_set.h).
// core/pipeline/preprocessing.h adds the adaptive surface over them.
#pragma once

#include <functional>
#include <memory>

#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"
#include "core/topology/patch_topology.h"

namespace tessera {

// The regular patches and rings of a validated control mesh whose topology is `topology`
// (topology.fits(mesh); the caller keys it by topologySha256): its positions refined through
// Far's levels and gathered into the pieces, with its UVs on the limit surface when it has any
// (`uvs`, when given, serves instead: LimitUvs of a mesh with the same UVs). `adaptive` is left
// empty. `checkpoint` (may be empty) is called every few thousand pieces and may throw. Throws
// TesseraError (invalid) for a mesh that does not fit the topology.
PatchSet reduceToPatches(const ControlMesh& mesh, const PatchTopology& topology,
                         const std::function<void()>& checkpoint,
                         std::shared_ptr<const LimitUvs> uvs = nullptr);

}  // namespace tessera
