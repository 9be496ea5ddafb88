#include "core/mesh/subdivision_rules.h"

#include <iterator>

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
         uint32_t(rules.triangleSubdivision) << 16 | uint32_t(rules.uvInterpolation) << 24;
}

std::optional<SubdivisionRules> rulesFromCode(uint32_t code) {
  const uint32_t boundary = code & 0xff, crease = code >> 8 & 0xff, triangles = code >> 16 & 0xff, uvs = code >> 24;
  if (boundary < 1 || boundary > 3 || crease > 1 || triangles > 1 || uvs > uint32_t(UvInterpolation::kBoundaries)) {
    return std::nullopt;
  }
  SubdivisionRules rules;
  rules.boundary = boundary == 1   ? BoundaryInterpolation::kEdgeOnly
                   : boundary == 2 ? BoundaryInterpolation::kEdgeAndCorner
                                   : BoundaryInterpolation::kNone;
  rules.creaseMethod = CreaseMethod(crease);
  rules.triangleSubdivision = TriangleSubdivision(triangles);
  rules.uvInterpolation = UvInterpolation(uvs);
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

namespace {
constexpr std::string_view kUvInterpolationNames[] = {"all", "none", "corners-only", "corners-plus1", "corners-plus2", "boundaries"};
}  // namespace

std::string_view uvInterpolationName(UvInterpolation rule) { return kUvInterpolationNames[size_t(rule)]; }

std::optional<UvInterpolation> parseUvInterpolation(std::string_view name) {
  for (size_t i = 0; i < std::size(kUvInterpolationNames); ++i) {
    if (name == kUvInterpolationNames[i]) return UvInterpolation(i);
  }
  return std::nullopt;
}

}  // namespace tessera
