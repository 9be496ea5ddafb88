// Wavefront OBJ reading (see core/mesh/obj_reader.h). One pass over the text a line at a time, tokens
// as string_views and numbers through std::from_chars: nothing is allocated per token, so the
// 11K-face benchmark characters read in a few milliseconds.
#include "core/mesh/obj_reader.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "core/base/error.h"
#include "core/mesh/obj_line.h"
#include "core/mesh/obj_tags.h"

namespace tessera {
namespace {

using obj_detail::failInvalid;
using obj_detail::failLimit;
using obj_detail::failUnsupported;
using obj_detail::formatNumber;
using obj_detail::LineTokens;
using obj_detail::NumberParse;
using obj_detail::parseFloat;
using obj_detail::parseWide;
using obj_detail::parseInt;
using obj_detail::quoted;
using obj_detail::SourceLine;

// Statements that carry nothing a control mesh keeps: normals, grouping, smoothing groups,
// materials and render attributes.
bool isSkippedStatement(std::string_view keyword) {
  static constexpr std::string_view kSkipped[] = {
      "vn",       "o",          "g",         "s",     "mg",
      "usemtl",   "mtllib",   "usemap",     "maplib",    "lod",   "bevel",
      "c_interp", "d_interp", "shadow_obj", "trace_obj", "ctech", "stech"};
  return std::find(std::begin(kSkipped), std::end(kSkipped), keyword) != std::end(kSkipped);
}

// Points, lines and free-form curves and surfaces are valid OBJ but nothing a subdivision control
// mesh can hold: refused rather than silently dropped. Returns null for other keywords.
const char* refusedElement(std::string_view keyword) {
  if (keyword == "p") return "point element";
  if (keyword == "l") return "line element";
  static constexpr std::string_view kFreeForm[] = {"vp",   "cstype", "deg",  "bmat", "step",
                                                   "curv", "curv2",  "surf", "parm", "trim",
                                                   "hole", "scrv",   "sp",   "end",  "con"};
  if (std::find(std::begin(kFreeForm), std::end(kFreeForm), keyword) != std::end(kFreeForm)) {
    return "free-form geometry";
  }
  return nullptr;
}

class ObjParser {
 public:
  ObjParser(const std::string& source, const MeshLimits& limits)
      : source_(source), limits_(limits) {}

  void parseLine(std::string_view line, int lineNumber);
  ControlMesh finish();

 private:
  void parseVertex(LineTokens& tokens, const SourceLine& at);
  void parseTextureVertex(LineTokens& tokens, const SourceLine& at);
  int textureIndex(std::string_view afterSlash, const SourceLine& at);
  void keepUvsOfEveryCornerOrNone();
  double coordinate(std::string_view token, const char* axis, const SourceLine& at) const;
  void placeFarMeshesAtTheirCentre();
  void parseFace(LineTokens& tokens, const SourceLine& at);
  int faceVertexIndex(std::string_view token, const SourceLine& at);

  const std::string& source_;
  const MeshLimits& limits_;
  ControlMesh mesh_;
  obj_detail::TagReader tags_;
  std::vector<int> face_;    // the face being read, 0-based
  // Faces may name vertices defined further down, so absolute indices are range-checked at the
  // end; the line of the largest one is kept for the message.
  int largestIndex_ = -1;
  int largestIndexLine_ = 0;
  // Texture coordinates: per corner its vt (−1: none), the first face without one, and the line
  // of the largest vt index (range-checked at the end, as vertices are).
  std::vector<int> cornerUvs_;
  int firstFaceWithoutUv_ = -1, firstFaceWithoutUvLine_ = 0, firstFaceWithUvLine_ = 0;
  int largestUv_ = -1, largestUvLine_ = 0;
  std::vector<Vec3d> exact_;  // the positions as read, in double precision
};

void ObjParser::parseLine(std::string_view line, int lineNumber) {
  line = line.substr(0, line.find('#'));  // whole-line and trailing comments
  LineTokens tokens(line);
  std::string_view keyword;
  if (!tokens.next(keyword)) return;
  const SourceLine at{source_, lineNumber};
  if (keyword == "v") return parseVertex(tokens, at);
  if (keyword == "vt") return parseTextureVertex(tokens, at);
  if (keyword == "f") return parseFace(tokens, at);
  if (keyword == "t") return tags_.apply(tokens, at, mesh_);
  if (isSkippedStatement(keyword)) return;
  if (const char* element = refusedElement(keyword)) {
    failUnsupported(at, "OBJ statement " + quoted(keyword) + " (" + element + ") is not supported");
  }
  failInvalid(at, "unknown OBJ statement " + quoted(keyword));
}

void ObjParser::parseVertex(LineTokens& tokens, const SourceLine& at) {
  if (static_cast<int64_t>(mesh_.positions.size()) >= limits_.maxVertices) {
    failLimit(at, "more than " + std::to_string(limits_.maxVertices) + " vertices (the limit)");
  }
  static constexpr const char* kAxes[] = {"x", "y", "z"};
  double xyz[3];
  for (int axis = 0; axis < 3; ++axis) {
    std::string_view token;
    if (!tokens.next(token)) {
      failInvalid(at,
                  std::string("missing ") + kAxes[axis] + " coordinate: expected 'v x y z [w]'");
    }
    xyz[axis] = coordinate(token, kAxes[axis], at);
  }
  std::string_view extra;
  if (tokens.next(extra)) {
    float w = 0.0f;  // the rational weight means nothing to Catmull-Clark: read, then dropped
    if (parseFloat(extra, w) != NumberParse::kOk) {
      failInvalid(at, "bad w " + quoted(extra) + ": expected a number");
    }
  }
  if (tokens.next(extra)) {
    failInvalid(at,
                "unexpected " + quoted(extra) + " after the coordinates: expected 'v x y z [w]'");
  }
  mesh_.positions.emplace_back(float(xyz[0]), float(xyz[1]), float(xyz[2]));
  exact_.emplace_back(xyz[0], xyz[1], xyz[2]);
}

// "vt u [v [w]]": v defaults to 0 (OBJ); w, for 3D textures, is read and dropped.
void ObjParser::parseTextureVertex(LineTokens& tokens, const SourceLine& at) {
  if (static_cast<int64_t>(mesh_.uvs.size() / 2) >= limits_.maxVertices) {
    failLimit(at, "more than " + std::to_string(limits_.maxVertices) + " texture vertices (the limit)");
  }
  float uvw[3] = {0.0f, 0.0f, 0.0f};
  static constexpr const char* kAxes[] = {"u", "v", "w"};
  int read = 0;
  for (std::string_view token; read < 3 && tokens.next(token); ++read) uvw[read] = float(coordinate(token, kAxes[read], at));
  std::string_view extra;
  if (read == 0) failInvalid(at, "missing u coordinate: expected 'vt u [v [w]]'");
  if (tokens.next(extra)) failInvalid(at, "unexpected " + quoted(extra) + " after the coordinates: expected 'vt u [v [w]]'");
  mesh_.uvs.push_back(uvw[0]);
  mesh_.uvs.push_back(uvw[1]);
}

double ObjParser::coordinate(std::string_view token, const char* axis, const SourceLine& at) const {
  double value = 0.0;
  const NumberParse parsed = parseWide(token, value);
  if (parsed == NumberParse::kMalformed) {
    failInvalid(
        at, std::string("bad ") + axis + " coordinate " + quoted(token) + ": expected a number");
  }
  if (parsed == NumberParse::kBeyondFloat) {
    failInvalid(at, std::string(axis) + " coordinate " + quoted(token) +
                        " is outside the range of a 32-bit float");
  }
  if (!std::isfinite(value)) {
    failInvalid(at, std::string(axis) + " coordinate " + quoted(token) + " is not a finite number");
  }
  if (std::abs(value) > limits_.maxAbsCoordinate) {
    failLimit(at, std::string(axis) + " coordinate " + quoted(token) + " is beyond the limit of " +
                      formatNumber(limits_.maxAbsCoordinate) + " in absolute value");
  }
  return value;
}

// A mesh farther from the origin than kFarFromOrigin of its box diagonals would lose its detail in
// float positions (each rounds by up to 2⁻²⁴ of its magnitude, 2.4e-7 of the diagonal at 4
// diagonals, where the server's finest relative tolerance is 1e-6): its positions are taken
// relative to its box's centre, computed from the doubles read (docs/FAR-FROM-ORIGIN.md).
void ObjParser::placeFarMeshesAtTheirCentre() {
  constexpr double kFarFromOrigin = 4.0;
  if (exact_.empty()) return;
  Vec3d lo = exact_[0], hi = exact_[0];
  for (const Vec3d& p : exact_) {
    lo = Vec3d(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
    hi = Vec3d(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
  }
  const Vec3d centre = (lo + hi) * 0.5;
  const double far = std::max({std::abs(centre.x), std::abs(centre.y), std::abs(centre.z)});
  if (far <= kFarFromOrigin * length(hi - lo)) return;
  mesh_.origin = centre;
  for (size_t v = 0; v < exact_.size(); ++v) mesh_.positions[v] = Vec3(exact_[v] - centre);
}

void ObjParser::parseFace(LineTokens& tokens, const SourceLine& at) {
  if (static_cast<int64_t>(mesh_.faceSizes.size()) >= limits_.maxFaces) {
    failLimit(at, "more than " + std::to_string(limits_.maxFaces) + " faces (the limit)");
  }
  face_.clear();
  const size_t cornersBefore = cornerUvs_.size();
  for (std::string_view token; tokens.next(token);) {
    if (static_cast<int64_t>(face_.size()) >= limits_.maxFaceSize) {
      failLimit(at, "face has more than " + std::to_string(limits_.maxFaceSize) +
                        " vertices (the limit)");
    }
    face_.push_back(faceVertexIndex(token, at));
  }
  if (face_.size() < 3) {
    failInvalid(at, "face has " + std::to_string(face_.size()) +
                        (face_.size() == 1 ? " vertex" : " vertices") + "; at least 3 are needed");
  }
  const bool withUvs = cornerUvs_[cornersBefore] >= 0;
  for (size_t c = cornersBefore; c < cornerUvs_.size(); ++c) {
    if ((cornerUvs_[c] >= 0) != withUvs) failInvalid(at, "face gives texture coordinates for some corners but not all");
  }
  if (withUvs && firstFaceWithUvLine_ == 0) firstFaceWithUvLine_ = at.line;
  if (!withUvs && firstFaceWithoutUv_ < 0) firstFaceWithoutUv_ = mesh_.faceCount(), firstFaceWithoutUvLine_ = at.line;
  mesh_.faceSizes.push_back(static_cast<int>(face_.size()));
  mesh_.faceVertices.insert(mesh_.faceVertices.end(), face_.begin(), face_.end());
}

// The texture and normal indices after the vertex index must be well formed: "vt", "/vn" or
// "vt/vn" after the first slash (normals are not used: the limit surface has its own).
bool isAttributeSyntax(std::string_view afterSlash) {
  const size_t slash = afterSlash.find('/');
  const std::string_view texture = afterSlash.substr(0, slash);
  int ignored = 0;
  if (slash == std::string_view::npos) return parseInt(texture, ignored);
  return (texture.empty() || parseInt(texture, ignored)) &&
         parseInt(afterSlash.substr(slash + 1), ignored);
}

int ObjParser::faceVertexIndex(std::string_view token, const SourceLine& at) {
  const size_t slash = token.find('/');
  int index = 0;
  if (!parseInt(token.substr(0, slash), index) ||
      (slash != std::string_view::npos && !isAttributeSyntax(token.substr(slash + 1)))) {
    failInvalid(at, "bad face vertex " + quoted(token) +
                        ": expected v, v/vt, v//vn or v/vt/vn with integer indices");
  }
  if (index == 0) {
    failInvalid(at,
                "face vertex index 0 is invalid: OBJ indices start at 1 (or count back from -1)");
  }
  cornerUvs_.push_back(slash == std::string_view::npos ? -1 : textureIndex(token.substr(slash + 1), at));
  if (index > 0) {
    if (index - 1 > largestIndex_) {
      largestIndex_ = index - 1;
      largestIndexLine_ = at.line;
    }
    return index - 1;
  }
  // Negative indices count back from the last vertex read so far: -1 is the latest.
  const int64_t resolved = static_cast<int64_t>(mesh_.positions.size()) + index;
  if (resolved < 0) {
    failInvalid(at, "relative face vertex index " + std::to_string(index) +
                        " reaches before the first vertex (" +
                        std::to_string(mesh_.positions.size()) + " vertices read so far)");
  }
  return static_cast<int>(resolved);
}

// The vt of "v/vt" or "v/vt/vn" (−1 for "v//vn"), 0-based; negative ones count back from the
// latest vt read.
int ObjParser::textureIndex(std::string_view afterSlash, const SourceLine& at) {
  const std::string_view texture = afterSlash.substr(0, afterSlash.find('/'));
  int index = 0;
  if (texture.empty()) return -1;
  parseInt(texture, index);  // well formed: checked with the rest of the token
  if (index == 0) failInvalid(at, "texture vertex index 0 is invalid: OBJ indices start at 1 (or count back from -1)");
  if (index > 0) {
    if (index - 1 > largestUv_) largestUv_ = index - 1, largestUvLine_ = at.line;
    return index - 1;
  }
  const int64_t resolved = static_cast<int64_t>(mesh_.uvs.size() / 2) + index;
  if (resolved < 0) {
    failInvalid(at, "relative texture vertex index " + std::to_string(index) + " reaches before the first texture vertex (" +
                        std::to_string(mesh_.uvs.size() / 2) + " read so far)");
  }
  return static_cast<int>(resolved);
}

// A mesh has UVs when its faces name them; faces that name none beside faces that do leave the
// UVs undefined there, which is refused rather than guessed.
void ObjParser::keepUvsOfEveryCornerOrNone() {
  const bool anyUv = firstFaceWithUvLine_ > 0;
  if (!anyUv) {
    mesh_.uvs.clear();
    return;
  }
  if (firstFaceWithoutUv_ >= 0) {
    failInvalid(SourceLine{source_, firstFaceWithoutUvLine_},
                "face " + std::to_string(firstFaceWithoutUv_) + " has no texture coordinates, but the face on line " +
                    std::to_string(firstFaceWithUvLine_) + " has: give every face UVs or none");
  }
  if (largestUv_ >= int64_t(mesh_.uvs.size() / 2)) {
    failInvalid(SourceLine{source_, largestUvLine_}, "texture vertex index " + std::to_string(int64_t{largestUv_} + 1) +
                                                         " is out of range: the file has " + std::to_string(mesh_.uvs.size() / 2) +
                                                         " texture vertices");
  }
  mesh_.uvIndices = std::move(cornerUvs_);
}

ControlMesh ObjParser::finish() {
  if (largestIndex_ >= mesh_.vertexCount()) {
    failInvalid(SourceLine{source_, largestIndexLine_},
                "face vertex index " + std::to_string(int64_t{largestIndex_} + 1) +
                    " is out of range: the file has " + std::to_string(mesh_.vertexCount()) +
                    " vertices");
  }
  tags_.checkReferences(mesh_, source_);
  keepUvsOfEveryCornerOrNone();
  placeFarMeshesAtTheirCentre();
  try {
    validateControlMesh(mesh_, limits_);
  } catch (const TesseraError& error) {
    throw TesseraError(error.kind(), source_ + ": " + error.what());
  }
  return std::move(mesh_);
}

std::string readWholeFile(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) {
    throwInvalid("cannot read OBJ file '" + path + "': it is a directory");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throwInvalid("cannot open OBJ file '" + path + "': " + std::strerror(errno));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  std::string text(size > 0 ? static_cast<size_t>(size) : 0, '\0');
  if (size < 0 || !in.read(text.data(), size)) {
    throwInvalid("cannot read OBJ file '" + path + "'");
  }
  return text;
}

}  // namespace

ControlMesh readObj(std::string_view text, const std::string& sourceName,
                    const MeshLimits& limits) {
  // Windows editors may start a file with a UTF-8 byte order mark; it encodes nothing.
  constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
  if (text.substr(0, kByteOrderMark.size()) == kByteOrderMark) {
    text.remove_prefix(kByteOrderMark.size());
  }
  ObjParser parser(sourceName, limits);
  int lineNumber = 0;
  for (size_t begin = 0; begin <= text.size();) {
    size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    if (lineNumber == INT_MAX) {
      throwLimit(sourceName + ": more than " + std::to_string(INT_MAX) + " lines");
    }
    parser.parseLine(text.substr(begin, end - begin), ++lineNumber);
    begin = end + 1;
  }
  return parser.finish();
}

ControlMesh readObjFile(const std::string& path, const MeshLimits& limits) {
  return readObj(readWholeFile(path), path, limits);
}

}  // namespace tessera
