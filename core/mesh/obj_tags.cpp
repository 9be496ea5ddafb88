// OpenSubdiv `t` tags in OBJ files. The meaning of each tag follows OpenSubdiv 3.6's
// regression/common/far_utils.h: GetSdcOptions() for interpolateboundary, creasemethod and
// smoothtriangles, assignComponentTags() for crease, corner and hole. In particular
// `interpolateboundary 1` is Sdc's VTX_BOUNDARY_EDGE_AND_CORNER and `2` is VTX_BOUNDARY_EDGE_ONLY
// (RenderMan's numbering, not the order of Sdc's enum), and a crease tag lists vertex pairs
// (v0 v1 v2 v3 = edges v0-v1 and v2-v3) with one sharpness for all of them or one per pair.
#include "core/mesh/obj_tags.h"

#include <cmath>
#include <cstdint>
#include <string_view>

namespace tessera::obj_detail {
namespace {

std::string named(const Tag& tag) {
  return "'t " + printable(tag.name) + "'";
}

std::string headerText(const Tag& tag) {
  return std::to_string(tag.intCount) + "/" + std::to_string(tag.floatCount) + "/" +
         std::to_string(tag.stringCount);
}

// "N/M/K": how many int, float and string arguments follow.
bool parseHeader(std::string_view text, Tag& tag) {
  const size_t first = text.find('/');
  if (first == std::string_view::npos) return false;
  const size_t second = text.find('/', first + 1);
  if (second == std::string_view::npos) return false;
  return parseInt(text.substr(0, first), tag.intCount) &&
         parseInt(text.substr(first + 1, second - first - 1), tag.floatCount) &&
         parseInt(text.substr(second + 1), tag.stringCount) && tag.intCount >= 0 &&
         tag.floatCount >= 0 && tag.stringCount >= 0;
}

void parseArguments(const std::vector<std::string_view>& args, const SourceLine& at, Tag& tag) {
  size_t next = 0;
  for (int i = 0; i < tag.intCount; ++i, ++next) {
    int value = 0;
    if (!parseInt(args[next], value)) {
      failInvalid(at, "argument " + std::to_string(next + 1) + " of " + named(tag) +
                          " should be an integer, found " + quoted(args[next]));
    }
    tag.ints.push_back(value);
  }
  for (int i = 0; i < tag.floatCount; ++i, ++next) {
    float value = 0.0f;
    const NumberParse parsed = parseFloat(args[next], value);
    if (parsed != NumberParse::kOk) {
      failInvalid(at, "argument " + std::to_string(next + 1) + " of " + named(tag) +
                          (parsed == NumberParse::kMalformed
                               ? " should be a number, found "
                               : " is outside the range of a 32-bit float: ") +
                          quoted(args[next]));
    }
    tag.floats.push_back(value);
  }
  for (int i = 0; i < tag.stringCount; ++i, ++next) tag.strings.push_back(args[next]);
}

void requireHeader(const Tag& tag, const SourceLine& at, bool matches, const char* expected) {
  if (!matches) {
    failInvalid(at, named(tag) + " expects " + expected + ", but its header is " + headerText(tag));
  }
}

// Sharpness is a user value: refused, not clamped to 0 as far_utils.h does.
void requireSharpness(const Tag& tag, const SourceLine& at, float sharpness) {
  if (!std::isfinite(sharpness) || sharpness < 0.0f) {
    failInvalid(
        at, named(tag) + " sharpness " + formatNumber(sharpness) + " is not a finite number >= 0");
  }
}

void applyInterpolateBoundary(const Tag& tag, const SourceLine& at, ControlMesh& mesh) {
  requireHeader(tag, at, tag.intCount == 1 && tag.floatCount == 0 && tag.stringCount == 0,
                "one integer (1/0/0)");
  switch (tag.ints[0]) {
    case 0:
      mesh.rules.boundary = BoundaryInterpolation::kNone;
      return;
    case 1:
      mesh.rules.boundary = BoundaryInterpolation::kEdgeAndCorner;
      return;
    case 2:
      mesh.rules.boundary = BoundaryInterpolation::kEdgeOnly;
      return;
    default:
      failInvalid(at, "'t interpolateboundary' value " + std::to_string(tag.ints[0]) +
                          " is not 0 (none), 1 (edge and corner) or 2 (edge only)");
  }
}

// Face-varying boundaries only change how UVs are interpolated; Tessera reads no UVs.
void acceptFaceVaryingBoundary(const Tag& tag, const SourceLine& at) {
  requireHeader(tag, at, tag.intCount == 1 && tag.floatCount == 0 && tag.stringCount == 0,
                "one integer (1/0/0)");
}

void applyCreaseMethod(const Tag& tag, const SourceLine& at, ControlMesh& mesh) {
  requireHeader(tag, at, tag.intCount == 0 && tag.floatCount == 0 && tag.stringCount == 1,
                "one string (0/0/1)");
  const std::string_view method = tag.strings[0];
  if (method == "normal" || method == "uniform") {
    mesh.rules.creaseMethod = CreaseMethod::kUniform;
    return;
  }
  if (method == "chaikin") {
    mesh.rules.creaseMethod = CreaseMethod::kChaikin;
    return;
  }
  failInvalid(
      at, "'t creasemethod' value " + quoted(method) + " is not one of normal, uniform or chaikin");
}

// "catmark" keeps Catmull-Clark's own weights on triangles (Sdc's TRI_SUB_CATMARK default).
void applySmoothTriangles(const Tag& tag, const SourceLine& at, ControlMesh& mesh) {
  requireHeader(tag, at, tag.intCount == 0 && tag.floatCount == 0 && tag.stringCount == 1,
                "one string (0/0/1)");
  const std::string_view rule = tag.strings[0];
  if (rule == "catmark") {
    mesh.rules.triangleSubdivision = TriangleSubdivision::kCatmark;
    return;
  }
  if (rule == "smooth") {
    mesh.rules.triangleSubdivision = TriangleSubdivision::kSmooth;
    return;
  }
  failInvalid(at, "'t smoothtriangles' value " + quoted(rule) + " is not catmark or smooth");
}

bool isHierarchicalEdit(std::string_view name) {
  return name == "vertexedit" || name == "edgeedit" || name == "faceedit";
}

// Ids in tags are 0-based, unlike OBJ's face indices; the message says so.
void requireInRange(int index, int count, const char* tagName, const char* element,
                    const char* elements, int line, const std::string& source) {
  if (index < 0 || index >= count) {
    failInvalid(SourceLine{source, line}, std::string("'t ") + tagName + "' names " + element +
                                              " " + std::to_string(index) + ", but the mesh has " +
                                              std::to_string(count) + " " + elements +
                                              " (ids are 0-based)");
  }
}

}  // namespace

// Checks the header against the arguments actually present before reading any of them, so a
// header announcing millions of arguments costs nothing.
void TagReader::read(LineTokens& tokens, const SourceLine& at) {
  tag_.name = {};
  tag_.ints.clear();
  tag_.floats.clear();
  tag_.strings.clear();
  if (!tokens.next(tag_.name)) {
    failInvalid(at,
                "'t' needs a tag name and an argument-count header, e.g. 't crease 2/1/0 0 1 3'");
  }
  std::string_view header;
  if (!tokens.next(header) || !parseHeader(header, tag_)) {
    failInvalid(at, "expected an argument-count header ints/floats/strings such as 2/1/0 after " +
                        named(tag_) + (header.empty() ? "" : ", found " + quoted(header)));
  }
  arguments_.clear();
  for (std::string_view token; tokens.next(token);) arguments_.push_back(token);
  const int64_t announced = int64_t{tag_.intCount} + tag_.floatCount + tag_.stringCount;
  if (static_cast<int64_t>(arguments_.size()) != announced) {
    failInvalid(at, named(tag_) + " header " + headerText(tag_) + " announces " +
                        std::to_string(announced) + " arguments, but the line has " +
                        std::to_string(arguments_.size()));
  }
  parseArguments(arguments_, at, tag_);
}

void TagReader::applyCrease(const SourceLine& at, ControlMesh& mesh) {
  const Tag& tag = tag_;
  const int pairs = tag.intCount / 2;
  requireHeader(
      tag, at,
      tag.intCount >= 2 && tag.intCount % 2 == 0 &&
          (tag.floatCount == 1 || tag.floatCount == pairs) && tag.stringCount == 0,
      "pairs of vertex ids and one sharpness, or one per pair (2/1/0, 4/1/0, 4/2/0, ...)");
  for (int i = 0; i < pairs; ++i) {
    const CreaseEdge crease{tag.ints[2 * i], tag.ints[2 * i + 1],
                            tag.floats[tag.floatCount == 1 ? 0 : i]};
    if (crease.v0 == crease.v1) {
      failInvalid(at, named(tag) + " edge (" + std::to_string(crease.v0) + ", " +
                          std::to_string(crease.v1) + ") joins a vertex to itself");
    }
    requireSharpness(tag, at, crease.sharpness);
    mesh.creases.push_back(crease);
    creaseLines_.push_back(at.line);
  }
}

void TagReader::applyCorner(const SourceLine& at, ControlMesh& mesh) {
  const Tag& tag = tag_;
  requireHeader(tag, at,
                tag.intCount >= 1 && (tag.floatCount == 1 || tag.floatCount == tag.intCount) &&
                    tag.stringCount == 0,
                "vertex ids and one sharpness, or one per vertex (1/1/0, 3/1/0, 3/3/0, ...)");
  for (int i = 0; i < tag.intCount; ++i) {
    const CornerVertex corner{tag.ints[i], tag.floats[tag.floatCount == 1 ? 0 : i]};
    requireSharpness(tag, at, corner.sharpness);
    mesh.corners.push_back(corner);
    cornerLines_.push_back(at.line);
  }
}

void TagReader::applyHole(const SourceLine& at, ControlMesh& mesh) {
  requireHeader(tag_, at, tag_.intCount >= 1 && tag_.floatCount == 0 && tag_.stringCount == 0,
                "face ids only (1/0/0, 4/0/0, ...)");
  for (int face : tag_.ints) {
    mesh.holes.push_back(face);
    holeLines_.push_back(at.line);
  }
}

void TagReader::apply(LineTokens& tokens, const SourceLine& at, ControlMesh& mesh) {
  read(tokens, at);
  const std::string_view name = tag_.name;
  if (name == "crease") return applyCrease(at, mesh);
  if (name == "corner") return applyCorner(at, mesh);
  if (name == "hole") return applyHole(at, mesh);
  if (name == "interpolateboundary") return applyInterpolateBoundary(tag_, at, mesh);
  if (name == "facevaryinginterpolateboundary") return acceptFaceVaryingBoundary(tag_, at);
  if (name == "creasemethod") return applyCreaseMethod(tag_, at, mesh);
  if (name == "smoothtriangles") return applySmoothTriangles(tag_, at, mesh);
  if (isHierarchicalEdit(name)) {
    failUnsupported(at, named(tag_) + " (hierarchical edit) is not supported");
  }
  failUnsupported(at, named(tag_) + " (unknown tag) is not supported");
}

void TagReader::checkReferences(const ControlMesh& mesh, const std::string& source) const {
  for (size_t i = 0; i < mesh.creases.size(); ++i) {
    for (int vertex : {mesh.creases[i].v0, mesh.creases[i].v1}) {
      requireInRange(vertex, mesh.vertexCount(), "crease", "vertex", "vertices", creaseLines_[i],
                     source);
    }
  }
  for (size_t i = 0; i < mesh.corners.size(); ++i) {
    requireInRange(mesh.corners[i].vertex, mesh.vertexCount(), "corner", "vertex", "vertices",
                   cornerLines_[i], source);
  }
  for (size_t i = 0; i < mesh.holes.size(); ++i) {
    requireInRange(mesh.holes[i], mesh.faceCount(), "hole", "face", "faces", holeLines_[i], source);
  }
}

}  // namespace tessera::obj_detail
