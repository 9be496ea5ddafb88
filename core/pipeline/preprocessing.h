// Preprocessing, once per mesh: a control mesh validated, reduced to patches and rings through
// OpenSubdiv Far (core/topology/patch_builder.h), and the adaptive surface built over them
// (core/surface/adaptive_surface.h). What a server caches per mesh (server/meshes/patch_set_cache.h).
// What depends on the topology alone (MeshTopology) is made first and may be kept: a mesh with
// the same topologySha256 and moved vertices (an edit, a frame of an animation) reuses it.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/request/tessellation_options.h"
#include "core/rings/patch_set.h"
#include "core/surface/seam_topology.h"
#include "core/topology/patch_builder.h"
#include "core/topology/patch_topology.h"
#include "core/topology/preprocessing_options.h"

namespace tessera {

// Everything preprocessing reads from a mesh but its positions: Far's refinement and the pieces'
// layout (core/topology/patch_topology.h), and where roots meet (core/surface/seam_topology.h);
// and the UVs on the limit surface of the mesh it was built from (core/topology/limit_uvs.h),
// which serve any mesh with the same UV values (an edit moves vertices, not UVs).
struct MeshTopology {
  MeshTopology(const ControlMesh& mesh, const PreprocessingOptions& options);
  PatchTopology pieces;
  SeamTopology seams;
  std::vector<float> uvValues;
  std::shared_ptr<const LimitUvs> uvs;  // null without UVs
  size_t bytes() const;
};

// The topology of a validated mesh. A non-manifold mesh is refined as its manifold sheets
// (core/mesh/manifold_sheets.h). Throws TesseraError for unsupported input (features that cannot
// be reduced to the canonical pieces) and for a refinement over the options' limit.
std::shared_ptr<const MeshTopology> buildMeshTopology(const ControlMesh& mesh, const PreprocessingOptions& options = {});

// Validates the mesh and preprocesses it: buildMeshTopology, then the positions. Throws
// TesseraError for invalid or unsupported input and for a refinement over the options' limit.
PatchSet buildPatchSet(const ControlMesh& mesh, const PreprocessingOptions& options = {});
// The same for a mesh whose topology is already built (`topology`, from a mesh with the same
// topologySha256): only its positions are refined and gathered (its UVs too where their values
// differ from the topology's), and its surface built. Throws as above, and TesseraError
// (invalid) when the mesh's counts do not fit the topology.
PatchSet buildPatchSet(const ControlMesh& mesh, const MeshTopology& topology, const PreprocessingOptions& options = {});

// The finest tolerance, a fraction of the bounding-box diagonal, that a request with `options`
// asks anywhere on `mesh` (before any encoding's reserve): what to preprocess it for
// (PreprocessingOptions::finestRelativeTolerance). With a camera, the tolerance at the nearest
// corner of the mesh's box; 0 for a uniform level, which needs no tree.
double finestRelativeTolerance(const ControlMesh& mesh, const TessellationOptions& options);

}  // namespace tessera
