// The adaptive tessellations the vertex kernel's simulation and its device test both run, each
// with the CPU engine's mesh to match: every supported OpenSubdiv shape at 1e-2 (regular, FAS and
// EV-bottom leaves, creases, holes, non-manifold sheets), and the paper's characters at 1e-3.
#pragma once

#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/tessellate.h"
#include "core/rings/patch_set.h"
#include "core/stitching/vertex_evaluation.h"
#include "reference/models.h"

namespace tessera::cuda::testing {

struct VertexCase {
  std::string path;
  double tolerance;  // relative to the bounding-box diagonal
};

inline std::vector<VertexCase> vertexCases(bool characters) {
  std::vector<VertexCase> cases;
  if (characters) {
    for (const std::string& path : tessera::testing::benchmarkCharacters()) cases.push_back({path, 1e-3});
    return cases;
  }
  for (const std::string& path : tessera::testing::openSubdivShapes()) cases.push_back({path, 1e-2});
  // Fine enough to reach the deepest EV quadrants' stand-ins.
  cases.push_back({tessera::testing::modelsDir() + "/opensubdiv-shapes/catmark_pole8.obj", 1e-5});
  return cases;
}

// The case's mesh; empty when Tessera refuses the file (the hierarchical edits).
inline ControlMesh readCaseMesh(const std::string& path) {
  try {
    return readObjFile(path);
  } catch (const TesseraError& error) {
    if (error.kind() != ErrorKind::kUnsupported) throw;
    return {};
  }
}

inline TessellationOptions vertexCaseOptions(double tolerance, VertexEvaluation* evaluation) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(tolerance);
  options.maxTriangles = 100'000'000;
  options.vertexEvaluation = evaluation;
  return options;
}

}  // namespace tessera::cuda::testing
