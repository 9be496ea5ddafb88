// A mesh's subdivision rules (Sdc options) by name, for people, and as one number, for the
// canonical encoding and the stores.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "core/mesh/control_mesh.h"

namespace tessera {

// tessera.v1.BoundaryInterpolation's number: 1 edge-only, 2 edge-and-corner, 3 none.
uint32_t boundaryCode(BoundaryInterpolation boundary);

// boundaryCode | crease method << 8 (0 uniform, 1 Chaikin) | triangle rule << 16 (0 Catmull-Clark,
// 1 smooth) | UV interpolation << 24 (UvInterpolation's order, 0 linear everywhere). Encodings
// written before the crease and triangle rules were accepted hold only the boundary code, which
// reads back as uniform creases, Catmull-Clark triangles and OpenSubdiv's default for UVs.
uint32_t rulesCode(const SubdivisionRules& rules);
// nullopt for a number no rules encode.
std::optional<SubdivisionRules> rulesFromCode(uint32_t code);

// "edge-only", "edge-and-corner", "none"; "uniform", "chaikin"; "catmark", "smooth" (the names of
// OpenSubdiv's OBJ tags and of the client's flags).
std::string_view boundaryName(BoundaryInterpolation boundary);
std::string_view creaseMethodName(CreaseMethod method);
std::string_view triangleSubdivisionName(TriangleSubdivision rule);
// "all", "none", "corners-only", "corners-plus1", "corners-plus2", "boundaries" (OpenSubdiv's
// FVAR_LINEAR_* names); nullopt for any other name.
std::string_view uvInterpolationName(UvInterpolation rule);
std::optional<UvInterpolation> parseUvInterpolation(std::string_view name);

}  // namespace tessera
