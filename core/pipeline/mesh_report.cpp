#include "core/pipeline/mesh_report.h"

#include <set>
#include <utility>

#include "core/base/error.h"
#include "core/mesh/subdivision_rules.h"
#include "core/pipeline/preprocessing.h"

namespace tessera {

std::string ringKind(const RingSet& rings, size_t r) {
  RingRules rules = rings.rules(r);
  if (rules.evRule == EvRule::kCorner) return "corner";
  if (rules.shape.open) return "boundary";
  if (rules.evRule == EvRule::kCrease) return "crease";
  for (int s = 0; s < rules.shape.spokeCount(); ++s) {
    if (rules.spokeSharp(s)) return "dart";
  }
  return "interior";
}

namespace {

void describeControlMesh(const ControlMesh& mesh, MeshReport& report) {
  report.vertices = mesh.vertexCount();
  report.faces = mesh.faceCount();
  std::map<std::pair<int, int>, int> edgeFaces;
  std::vector<int> valence(mesh.vertexCount(), 0);
  size_t offset = 0;
  for (int size : mesh.faceSizes) {
    ++report.faceSizes[size];
    for (int k = 0; k < size; ++k) {
      int a = mesh.faceVertices[offset + k], b = mesh.faceVertices[offset + (k + 1) % size];
      if (++edgeFaces[{std::min(a, b), std::max(a, b)}] == 1) ++valence[a], ++valence[b];
    }
    offset += size;
  }
  report.edges = static_cast<int>(edgeFaces.size());
  for (const auto& [edge, faces] : edgeFaces) report.boundaryEdges += faces == 1 ? 1 : 0;
  for (int v : valence) {
    if (v == 0)
      ++report.unusedVertices;
    else
      ++report.valences[v];
  }
  report.creases = static_cast<int>(mesh.creases.size());
  for (const auto& c : mesh.creases) report.infiniteCreases += c.sharpness >= kInfiniteSharpness;
  report.corners = static_cast<int>(mesh.corners.size());
  report.holes = static_cast<int>(mesh.holes.size());
  report.boundaryInterpolation = boundaryName(mesh.rules.boundary);
  report.creaseMethod = creaseMethodName(mesh.rules.creaseMethod);
  report.triangleSubdivision = triangleSubdivisionName(mesh.rules.triangleSubdivision);
}

}  // namespace

MeshReport inspectMesh(const ControlMesh& mesh) {
  MeshReport report;
  describeControlMesh(mesh, report);
  try {
    PatchSet set = buildPatchSet(mesh);
    report.nonManifoldEdges = set.stats.nonManifoldEdges;
    report.nonManifoldVertices = set.stats.nonManifoldVertices;
    report.regularPatches = static_cast<int>(set.regular.size());
    for (size_t r = 0; r < set.rings.size(); ++r) {
      ++report.ringsByKind[ringKind(set.rings, r)][set.rings.shapes[r].sectors];
    }
    report.locallyRefinedFaces = set.stats.locallyRefinedFaces;
    report.isolationLevel = set.stats.isolationLevel;
  } catch (const TesseraError& e) {
    report.refusal = e.what();
  }
  return report;
}

}  // namespace tessera
