// Preprocessing, once per mesh: a control mesh validated, reduced to patches and rings through
// OpenSubdiv Far (core/topology/patch_builder.h), and the adaptive surface built over them
// (core/surface/adaptive_surface.h). What a server caches per mesh (server/meshes/patch_set_cache.h).
#pragma once

#include "core/mesh/control_mesh.h"
#include "core/request/tessellation_options.h"
#include "core/rings/patch_set.h"
#include "core/topology/patch_builder.h"

namespace tessera {

// A non-manifold mesh is refined as its manifold sheets (core/mesh/manifold_sheets.h). Throws
// TesseraError for invalid or unsupported input (features that cannot be reduced to the
// canonical pieces) and for a refinement over the options' limit.
PatchSet buildPatchSet(const ControlMesh& mesh, const PreprocessingOptions& options = {});

// The finest tolerance, a fraction of the bounding-box diagonal, that a request with `options`
// asks anywhere on `mesh` (before any encoding's reserve): what to preprocess it for
// (PreprocessingOptions::finestRelativeTolerance). With a camera, the tolerance at the nearest
// corner of the mesh's box; 0 for a uniform level, which needs no tree.
double finestRelativeTolerance(const ControlMesh& mesh, const TessellationOptions& options);

}  // namespace tessera
