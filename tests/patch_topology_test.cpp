// Edits reuse topology (core/topology/patch_topology.h, core/pipeline/preprocessing.h): a mesh
// preprocessed through the topology of another mesh with the same topologySha256 must give what
// preprocessing it from scratch gives, bit for bit — the patches, the rings and the GLB's
// triangles — on every feature class the topology holds (EVs and poles, semi-sharp creases and
// corners, boundaries and their rules, holes, n-gons, non-manifold sheets, UVs). The scratch path
// is the reference (patch_set_test.cpp holds it to OpenSubdiv's limit surface).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "core/base/error.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
#include "reference/models.h"
#include "tests/support/mesh_equality.h"

namespace tessera {
namespace {

// Every vertex moved by a low-frequency field, up to 2 % of the box's diagonal: an edit.
ControlMesh movedCopy(const ControlMesh& mesh, double phase) {
  Vec3 lo, hi;
  mesh.bounds(lo, hi);
  const double diagonal = length(Vec3d(hi) - Vec3d(lo));
  ControlMesh moved = mesh;
  for (Vec3& p : moved.positions) {
    const double s = (p.x + 2 * p.y + 3 * p.z) / (diagonal > 0 ? diagonal : 1);
    p = p + Vec3(float(0.02 * diagonal * std::sin(6.0 * s + phase)), float(0.01 * diagonal * std::cos(5.0 * s)),
                 float(0.015 * diagonal * std::sin(4.0 * s - phase)));
  }
  return moved;
}

template <typename T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// "" when the two patch sets' pieces hold the same bits; else the first field that differs.
std::string pieceDifference(const PatchSet& a, const PatchSet& b) {
  if (!sameBytes(a.regular.bspline, b.regular.bspline)) return "regular nets";
  if (a.regular.levels != b.regular.levels) return "regular levels";
  if (!sameBytes(a.regular.domains, b.regular.domains)) return "regular domains";
  if (!sameBytes(a.rings.points, b.rings.points)) return "ring points";
  if (!sameBytes(a.rings.centers, b.rings.centers)) return "ring centres";
  if (a.rings.levels != b.rings.levels || a.rings.sharpSpokes != b.rings.sharpSpokes) return "ring levels or spokes";
  if (!sameBytes(a.rings.sectorDomains, b.rings.sectorDomains) || a.rings.sectorOwned != b.rings.sectorOwned) {
    return "ring sectors";
  }
  if (a.stats.locallyRefinedFaces != b.stats.locallyRefinedFaces || a.stats.isolationLevel != b.stats.isolationLevel) {
    return "stats";
  }
  return "";
}

TessellationOptions atRelative(double eps) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(eps);
  return options;
}

// The edit `moved` of `rest` (whose topology is `topology`), from scratch and through the
// topology, at ε = 1e-3.
void expectSameAsFromScratch(const std::string& name, const ControlMesh& rest, const MeshTopology& topology,
                             const ControlMesh& moved) {
  SCOPED_TRACE(name);
  ASSERT_EQ(topologySha256(rest), topologySha256(moved));
  PreprocessingOptions preprocessing;
  preprocessing.finestRelativeTolerance = 1e-3;
  const PatchSet scratch = buildPatchSet(moved, preprocessing);
  const PatchSet reused = buildPatchSet(moved, topology, preprocessing);
  EXPECT_EQ(pieceDifference(scratch, reused), "");
  const TessellationResult a = tessellate(scratch, moved, atRelative(1e-3));
  const TessellationResult b = tessellate(reused, moved, atRelative(1e-3));
  EXPECT_EQ(testing::meshDifference(a.mesh, b.mesh), "");
  EXPECT_GT(a.summary.triangles, 0);
}

void expectSameAsFromScratch(const std::string& name, const ControlMesh& rest, const ControlMesh& moved) {
  expectSameAsFromScratch(name, rest, *buildMeshTopology(rest), moved);
}

// Null for a shape Tessera refuses (patch_set_test.cpp checks those refusals).
std::shared_ptr<const MeshTopology> topologyOrNull(const std::string& path, ControlMesh& mesh) {
  try {
    mesh = readObjFile(path);
    return buildMeshTopology(mesh);
  } catch (const TesseraError&) {
    return nullptr;
  }
}

TEST(PatchTopology, AnEditOfEveryOpenSubdivShapeThroughItsTopologyIsTheSameAsFromScratch) {
  int checked = 0;
  for (const std::string& path : testing::openSubdivShapes()) {
    ControlMesh rest;
    const std::shared_ptr<const MeshTopology> topology = topologyOrNull(path, rest);
    if (!topology) continue;
    expectSameAsFromScratch(testing::baseName(path), rest, *topology, movedCopy(rest, 0.3));
    ++checked;
  }
  EXPECT_GT(checked, 60);
}

TEST(PatchTopology, AnEditOfACharacterWithUvsThroughItsTopologyIsTheSameAsFromScratch) {
  const ControlMesh rest = readObjFile(testing::modelsDir() + "/bigguy.obj");
  ASSERT_TRUE(rest.hasUvs());
  expectSameAsFromScratch("bigguy", rest, movedCopy(rest, 1.1));
}

// Semi-sharp creases running into a boundary with the edge-and-corner rule (valence-2 corners),
// a hole, a pentagon and a triangle: every tag the topology keeps, on one small mesh.
ControlMesh taggedSheet() {
  ControlMesh mesh;
  const int n = 5;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) mesh.positions.emplace_back(float(i), float(j), float((i * j) % 3) * 0.2f);
  }
  auto at = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (i == 2 && j == 2) continue;  // replaced by a pentagon and a triangle below
      mesh.faceSizes.push_back(4);
      mesh.faceVertices.insert(mesh.faceVertices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  const int centre = int(mesh.positions.size());
  mesh.positions.emplace_back(2.5f, 2.5f, 0.4f);
  mesh.faceSizes.insert(mesh.faceSizes.end(), {5, 3});
  mesh.faceVertices.insert(mesh.faceVertices.end(), {at(2, 2), at(3, 2), at(3, 3), centre, at(2, 3)});
  mesh.faceVertices.insert(mesh.faceVertices.end(), {centre, at(3, 3), at(2, 3)});
  for (int i = 0; i < n; ++i) mesh.creases.push_back({at(i, 1), at(i + 1, 1), 2.5f});
  for (int j = 0; j < n; ++j) mesh.creases.push_back({at(3, j), at(3, j + 1), 7.0f});
  mesh.corners.push_back({at(1, 4), 1.5f});
  mesh.holes.push_back(0);
  mesh.rules.boundary = BoundaryInterpolation::kEdgeAndCorner;
  return mesh;
}

TEST(PatchTopology, AnEditOfASheetWithEveryTagThroughItsTopologyIsTheSameAsFromScratch) {
  const ControlMesh rest = taggedSheet();
  expectSameAsFromScratch("tagged sheet", rest, movedCopy(rest, 2.0));
}

TEST(PatchTopology, TheTopologyHashFollowsEverythingButThePositionsAndUvValues) {
  const ControlMesh rest = taggedSheet();
  const std::string hash = topologySha256(rest);
  EXPECT_EQ(topologySha256(movedCopy(rest, 0.5)), hash);
  ControlMesh uvs = rest;
  uvs.uvs = {0, 0, 1, 0, 1, 1};
  uvs.uvIndices.assign(rest.faceVertices.size(), 0);
  ControlMesh otherUvValues = uvs;
  otherUvValues.uvs = {0.5f, 0, 1, 0.25f, 1, 1};
  EXPECT_EQ(topologySha256(otherUvValues), topologySha256(uvs));
  EXPECT_NE(topologySha256(uvs), hash);

  auto changed = [&](auto change) {
    ControlMesh mesh = rest;
    change(mesh);
    return topologySha256(mesh);
  };
  EXPECT_NE(changed([](ControlMesh& m) { m.creases[0].sharpness = 2.0f; }), hash);
  EXPECT_NE(changed([](ControlMesh& m) { m.creases.pop_back(); }), hash);
  EXPECT_NE(changed([](ControlMesh& m) { m.corners[0].vertex += 1; }), hash);
  EXPECT_NE(changed([](ControlMesh& m) { m.holes = {1}; }), hash);
  EXPECT_NE(changed([](ControlMesh& m) { m.rules.boundary = BoundaryInterpolation::kEdgeOnly; }), hash);
  EXPECT_NE(changed([](ControlMesh& m) { m.rules.creaseMethod = CreaseMethod::kChaikin; }), hash);
  EXPECT_NE(changed([](ControlMesh& m) { std::swap(m.faceVertices[0], m.faceVertices[1]); }), hash);
  EXPECT_NE(changed([](ControlMesh& m) { m.positions.emplace_back(9.0f, 9.0f, 9.0f); }), hash);
}

TEST(PatchTopology, AMeshThatDoesNotFitTheTopologyIsRefusedByName) {
  const ControlMesh rest = taggedSheet();
  const std::shared_ptr<const MeshTopology> topology = buildMeshTopology(rest);
  ControlMesh more = rest;
  more.positions.emplace_back(9.0f, 9.0f, 9.0f);
  try {
    buildPatchSet(more, *topology);
    FAIL() << "a mesh with another vertex count was preprocessed through the topology";
  } catch (const TesseraError& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kInvalidInput);
    EXPECT_NE(std::string(error.what()).find("vertices"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace tessera
