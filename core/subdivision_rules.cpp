#include "core/subdivision_rules.h"

namespace tessera {

uint32_t boundaryCode(BoundaryInterpolation boundary) {
  switch (boundary) {
    case BoundaryInterpolation::kEdgeOnly:
      return 1;
    case BoundaryInterpolation::kEdgeAndCorner:
      return 2;
    case BoundaryInterpolation::kNone:
      return 3;
  }
  return 1;
}

uint32_t rulesCode(const SubdivisionRules& rules) {
  return boundaryCode(rules.boundary) | uint32_t(rules.creaseMethod) << 8 |
         uint32_t(rules.triangleSubdivision) << 16;
}

std::optional<SubdivisionRules> rulesFromCode(uint32_t code) {
  const uint32_t boundary = code & 0xff, crease = code >> 8 & 0xff, triangles = code >> 16;
  if (boundary < 1 || boundary > 3 || crease > 1 || triangles > 1) return std::nullopt;
  SubdivisionRules rules;
  rules.boundary = boundary == 1   ? BoundaryInterpolation::kEdgeOnly
                   : boundary == 2 ? BoundaryInterpolation::kEdgeAndCorner
                                   : BoundaryInterpolation::kNone;
  rules.creaseMethod = CreaseMethod(crease);
  rules.triangleSubdivision = TriangleSubdivision(triangles);
  return rules;
}

std::string_view boundaryName(BoundaryInterpolation boundary) {
  switch (boundary) {
    case BoundaryInterpolation::kEdgeOnly:
      return "edge-only";
    case BoundaryInterpolation::kEdgeAndCorner:
      return "edge-and-corner";
    case BoundaryInterpolation::kNone:
      return "none";
  }
  return "edge-only";
}

std::string_view creaseMethodName(CreaseMethod method) {
  return method == CreaseMethod::kChaikin ? "chaikin" : "uniform";
}

std::string_view triangleSubdivisionName(TriangleSubdivision rule) {
  return rule == TriangleSubdivision::kSmooth ? "smooth" : "catmark";
}

}  // namespace tessera
