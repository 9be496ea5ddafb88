// OpenSubdiv's `t` tag lines inside an OBJ file (the form of its regression shapes,
// regression/shapes/*.h, as read by regression/common/far_utils.h):
//   t <name> <ints>/<floats>/<strings> <int args...> <float args...> <string args...>
// Internal to the OBJ reader; not part of core's API.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/mesh/obj_line.h"

namespace tessera::obj_detail {

// One tag line split by its header into typed arguments.
struct Tag {
  std::string_view name;
  int intCount = 0, floatCount = 0, stringCount = 0;  // as the header announces them
  std::vector<int> ints;
  std::vector<float> floats;
  std::vector<std::string_view> strings;
};

// Reads `t` lines into a mesh and remembers where each crease, corner and hole came from.
class TagReader {
 public:
  // Reads the rest of a `t` line (after the `t`) and applies it to the mesh: creases, corners
  // and holes are appended, boundary interpolation is set, and tags that would change the
  // surface in ways Tessera does not implement are refused.
  void apply(LineTokens& tokens, const SourceLine& at, ControlMesh& mesh);

  // Tags may come before the vertices and faces they name, so their ids are range-checked once
  // the whole file has been read.
  void checkReferences(const ControlMesh& mesh, const std::string& source) const;

 private:
  void read(LineTokens& tokens, const SourceLine& at);
  void applyCrease(const SourceLine& at, ControlMesh& mesh);
  void applyCorner(const SourceLine& at, ControlMesh& mesh);
  void applyHole(const SourceLine& at, ControlMesh& mesh);

  // Reused from line to line: the benchmark characters have thousands of crease tags.
  Tag tag_;
  std::vector<std::string_view> arguments_;
  // The source line of each crease, corner and hole the tags added, in mesh order.
  std::vector<int> creaseLines_, cornerLines_, holeLines_;
};

}  // namespace tessera::obj_detail
