// Reads a control mesh from Wavefront OBJ text with OpenSubdiv's `t` tag lines (crease, corner,
// hole, interpolateboundary, ...), the form of OpenSubdiv's regression shapes.
//
// Geometry: `v x y z [w]` (w ignored) and `f` with `v`, `v/vt`, `v//vn`, `v/vt/vn` indices, 1-based
// or negative (relative to the vertices read so far). Texture coordinates, normals, groups,
// smoothing groups and materials are skipped. Tags refer to vertices and faces by 0-based id.
//
// Every problem is a TesseraError whose message starts with "<sourceName>:<line>: " where a line
// is to blame: kInvalidInput for malformed text, kUnsupported for features Tessera refuses
// (Chaikin creases, VTX_BOUNDARY_NONE, smooth triangles, hierarchical edits, unknown tags,
// free-form geometry), kLimitExceeded past `limits`. The returned mesh has passed
// validateControlMesh(); it may be non-manifold (see core/mesh/manifold_sheets.h).
#pragma once

#include <string>
#include <string_view>

#include "core/mesh/control_mesh.h"

namespace tessera {

ControlMesh readObj(std::string_view text, const std::string& sourceName,
                    const MeshLimits& limits = {});

// Reads the whole file, then readObj() with the path as the source name.
ControlMesh readObjFile(const std::string& path, const MeshLimits& limits = {});

}  // namespace tessera
