// cutIntoSheets: manifold meshes pass through untouched; non-manifold edges, flipped faces and
// bow-tie vertices are cut into manifold sheets whose vertices carry the sharpness OpenSubdiv
// gives the input's; and the sheets' limit surface is the input's, face by face, as OpenSubdiv
// evaluates both (the claim docs/NONMANIFOLD.md proves).
#include "core/mesh/manifold_sheets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "core/base/error.h"
#include "core/mesh/obj_reader.h"
#include "reference/bfr_reference.h"
#include "reference/far_patch_reference.h"
#include "reference/models.h"
#include "tests/support/model_stats.h"

namespace tessera {
namespace {

// Appends a face; returns its index.
int addFace(ControlMesh& mesh, std::initializer_list<int> vertices) {
  mesh.faceSizes.push_back(static_cast<int>(vertices.size()));
  mesh.faceVertices.insert(mesh.faceVertices.end(), vertices);
  return mesh.faceCount() - 1;
}

ControlMesh withVertices(int count) {
  ControlMesh mesh;
  for (int i = 0; i < count; ++i) mesh.positions.emplace_back(float(i), float(i % 3), float(i % 5) * 0.5f);
  return mesh;
}

// The unit cube with outward quads, vertex i at its bits (x = bit 0, y = bit 1, z = bit 2).
ControlMesh makeCube(int firstVertex = 0, ControlMesh mesh = withVertices(8)) {
  const int v = firstVertex;
  addFace(mesh, {v + 0, v + 2, v + 3, v + 1});
  addFace(mesh, {v + 4, v + 5, v + 7, v + 6});
  addFace(mesh, {v + 0, v + 1, v + 5, v + 4});
  addFace(mesh, {v + 2, v + 6, v + 7, v + 3});
  addFace(mesh, {v + 0, v + 4, v + 6, v + 2});
  addFace(mesh, {v + 1, v + 3, v + 7, v + 5});
  return mesh;
}

// An n x n grid of quads: a disk whose border is one boundary loop.
ControlMesh makeGrid(int n) {
  ControlMesh mesh = withVertices((n + 1) * (n + 1));
  for (int row = 0; row < n; ++row) {
    for (int col = 0; col < n; ++col) {
      const int v = row * (n + 1) + col;
      addFace(mesh, {v, v + 1, v + n + 2, v + n + 1});
    }
  }
  return mesh;
}

// Three fins of two quads each on the chain 0-1-2 (an interior non-manifold crease at vertex 1).
ControlMesh threeFinsOnAChain() {
  ControlMesh mesh = withVertices(3 + 3 * 3);
  for (int fin = 0; fin < 3; ++fin) {
    const int a = 3 + 3 * fin;
    addFace(mesh, {0, 1, a + 1, a});
    addFace(mesh, {1, 2, a + 2, a + 1});
  }
  return mesh;
}

// Three quads on edge (0, 1), the simplest non-manifold edge.
ControlMesh threeQuadsOnOneEdge() {
  ControlMesh mesh = withVertices(8);
  addFace(mesh, {0, 2, 3, 1});
  addFace(mesh, {1, 5, 4, 0});
  addFace(mesh, {0, 6, 7, 1});
  return mesh;
}

float cornerSharpness(const ControlMesh& mesh, int vertex) {
  for (const CornerVertex& c : mesh.corners) {
    if (c.vertex == vertex) return c.sharpness;
  }
  return 0.0f;
}

// Every sheet vertex's copies of one input vertex.
std::vector<int> copiesOf(const ManifoldSheets& cut, int vertex) {
  std::vector<int> copies;
  for (int s = 0; s < int(cut.inputVertex.size()); ++s) {
    if (cut.inputVertex[s] == vertex) copies.push_back(s);
  }
  return copies;
}

// The sheets keep the faces and where their corners are, and are manifold.
void expectSheetsOfInput(const ManifoldSheets& cut, const ControlMesh& input) {
  ASSERT_EQ(cut.sheets.faceSizes, input.faceSizes);
  ASSERT_EQ(cut.sheets.faceVertices.size(), input.faceVertices.size());
  ASSERT_EQ(cut.inputVertex.size(), cut.sheets.positions.size());
  for (size_t c = 0; c < input.faceVertices.size(); ++c) {
    const int s = cut.sheets.faceVertices[c];
    EXPECT_EQ(cut.inputVertex[s], input.faceVertices[c]) << "corner " << c;
    const Vec3 &a = cut.sheets.positions[s], &b = input.positions[input.faceVertices[c]];
    EXPECT_TRUE(a.x == b.x && a.y == b.y && a.z == b.z) << "corner " << c;
  }
  EXPECT_FALSE(cutIntoSheets(cut.sheets).cut()) << "the sheets are still non-manifold";
}

TEST(ManifoldSheets, ManifoldMeshesAreNotCut) {
  for (const ControlMesh& mesh : {makeCube(), makeGrid(1), makeGrid(7)}) {
    const ManifoldSheets cut = cutIntoSheets(mesh);
    EXPECT_FALSE(cut.cut());
    EXPECT_EQ(&cut.sheetsOf(mesh), &mesh);
    EXPECT_EQ(&cut.seamsOf(mesh), &mesh);
    EXPECT_TRUE(cut.sheets.faceVertices.empty());  // nothing copied
  }
  ControlMesh withUnused = makeGrid(3);
  withUnused.positions.emplace_back(5.0f, 5.0f, 5.0f);
  EXPECT_FALSE(cutIntoSheets(withUnused).cut());
}

// Three quads on edge (0, 1): each keeps its own copy of the edge, whose ends (one non-manifold
// edge and boundary edges each) OpenSubdiv makes corners.
TEST(ManifoldSheets, EdgeSharedByThreeFacesIsCutIntoThreeBoundaries) {
  ControlMesh mesh = threeQuadsOnOneEdge();
  const ManifoldSheets cut = cutIntoSheets(mesh);
  EXPECT_TRUE(cut.cut());
  EXPECT_EQ(cut.nonManifoldEdges, 1);
  EXPECT_EQ(cut.nonManifoldVertices, 2);
  expectSheetsOfInput(cut, mesh);
  for (int v : {0, 1}) {
    EXPECT_EQ(copiesOf(cut, v).size(), 3u);
    for (int s : copiesOf(cut, v)) EXPECT_EQ(cornerSharpness(cut.sheets, s), kInfiniteSharpness);
    EXPECT_EQ(cornerSharpness(cut.seams, v), kInfiniteSharpness);
  }
  ASSERT_EQ(cut.seams.creases.size(), 1u);
  EXPECT_EQ(cut.seams.creases[0].sharpness, kInfiniteSharpness);
}

// Three fins of two quads each on the chain 0-1-2: vertex 1 has two non-manifold edges, no
// boundary edge and six faces on five edges, so it keeps the crease rule; the chain's ends are
// corners.
TEST(ManifoldSheets, InteriorNonManifoldCreaseKeepsTheCreaseRule) {
  ControlMesh mesh = threeFinsOnAChain();
  const ManifoldSheets cut = cutIntoSheets(mesh);
  expectSheetsOfInput(cut, mesh);
  EXPECT_EQ(cut.nonManifoldEdges, 2);
  EXPECT_EQ(copiesOf(cut, 1).size(), 3u);
  for (int s : copiesOf(cut, 1)) EXPECT_EQ(cornerSharpness(cut.sheets, s), 0.0f);
  for (int s : copiesOf(cut, 0)) EXPECT_EQ(cornerSharpness(cut.sheets, s), kInfiniteSharpness);
  EXPECT_EQ(cornerSharpness(cut.seams, 1), 0.0f);
}

TEST(ManifoldSheets, FlippedFaceMakesItsEdgesSharp) {
  ControlMesh mesh = makeCube();
  std::swap(mesh.faceVertices[1], mesh.faceVertices[3]);  // face 0: 0 1 3 2
  const ManifoldSheets cut = cutIntoSheets(mesh);
  EXPECT_EQ(cut.nonManifoldEdges, 4);
  expectSheetsOfInput(cut, mesh);
}

TEST(ManifoldSheets, BowTieVertexGetsACornerPerFan) {
  ControlMesh mesh = withVertices(5);
  addFace(mesh, {0, 1, 2});
  addFace(mesh, {0, 3, 4});
  const ManifoldSheets cut = cutIntoSheets(mesh);
  EXPECT_EQ(cut.nonManifoldEdges, 0);
  EXPECT_EQ(cut.nonManifoldVertices, 1);
  expectSheetsOfInput(cut, mesh);
  ASSERT_EQ(copiesOf(cut, 0).size(), 2u);
  for (int s : copiesOf(cut, 0)) EXPECT_EQ(cornerSharpness(cut.sheets, s), kInfiniteSharpness);
}

// A two-sided quad with a fin on one edge: both sides meet along three manifold edges, so the
// fin's edge stays one sheet edge for them, which must stay infinitely sharp.
TEST(ManifoldSheets, TwoSidedFaceKeepsItsNonManifoldEdgeSharp) {
  ControlMesh mesh = withVertices(6);
  addFace(mesh, {0, 1, 2, 3});
  addFace(mesh, {3, 2, 1, 0});
  addFace(mesh, {0, 1, 4, 5});
  const ManifoldSheets cut = cutIntoSheets(mesh);
  expectSheetsOfInput(cut, mesh);
  bool sharp = false;
  for (const CreaseEdge& c : cut.sheets.creases) {
    sharp |= std::set<int>{cut.inputVertex[c.v0], cut.inputVertex[c.v1]} == std::set<int>{0, 1} &&
             c.sharpness == kInfiniteSharpness;
  }
  EXPECT_TRUE(sharp);
}

TEST(ManifoldSheets, TopologicalCornersStaySharpenedOnlyWhereTheInputsWere) {
  ControlMesh mesh = threeQuadsOnOneEdge();
  mesh.rules.boundary = BoundaryInterpolation::kEdgeAndCorner;
  const ManifoldSheets cut = cutIntoSheets(mesh);
  EXPECT_EQ(cut.sheets.rules.boundary, BoundaryInterpolation::kEdgeOnly);
  for (int v : {2, 3, 4, 5, 6, 7}) EXPECT_EQ(cornerSharpness(cut.sheets, v), kInfiniteSharpness) << v;
}

TEST(ManifoldSheets, BoundaryRuleNoneIsRefusedByName) {
  ControlMesh mesh = withVertices(5);
  addFace(mesh, {0, 1, 2});
  addFace(mesh, {0, 3, 4});
  mesh.rules.boundary = BoundaryInterpolation::kNone;
  try {
    cutIntoSheets(mesh);
    ADD_FAILURE() << "accepted";
  } catch (const TesseraError& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kUnsupported);
    EXPECT_NE(std::string(error.what()).find("\"none\""), std::string::npos) << error.what();
  }
  EXPECT_FALSE(cutIntoSheets(makeGrid(2)).cut());  // a manifold mesh under "none" is fine
}

TEST(ManifoldSheets, UnvalidatedMeshIsRefusedNotRead) {
  ControlMesh mesh = makeCube();
  mesh.faceVertices[5] = 99;
  EXPECT_THROW(cutIntoSheets(mesh), TesseraError);
  mesh = makeCube();
  mesh.faceVertices.pop_back();
  EXPECT_THROW(cutIntoSheets(mesh), TesseraError);
}

TEST(ManifoldSheets, ShapesAgreeWithTheStatsTable) {
  // Vertices whose faces form two fans without any edge being shared by three faces; the stats
  // table has no column for them.
  const std::set<std::string> bowTies = {"opensubdiv-shapes/catmark_gregory_test4.obj",
                                         "opensubdiv-shapes/catmark_nonman_verts.obj"};
  for (const testing::ModelStats& stats : testing::readModelStats()) {
    ControlMesh mesh;
    try {
      mesh = readObjFile(testing::modelsDir() + "/" + stats.file);
    } catch (const TesseraError&) {
      continue;  // shapes the reader refuses are covered by obj_reader_test
    }
    SCOPED_TRACE(stats.file);
    const ManifoldSheets cut = cutIntoSheets(mesh);
    EXPECT_EQ(cut.cut(), stats.nonmanifoldEdges > 0 || bowTies.count(stats.file) > 0);
    EXPECT_EQ(cut.nonManifoldEdges > 0, stats.nonmanifoldEdges > 0);
    if (cut.cut()) {
      expectSheetsOfInput(cut, mesh);
    }
  }
}

// The claim itself, checked by OpenSubdiv: its limit surface of the sheets equals its limit
// surface of the input at every sampled point of every face (Far's patches where Debian's Bfr
// 3.5.0 mis-evaluates valence-2 interior vertices).
template <typename Reference>
void expectSameLimitSurface(const ControlMesh& input, const ControlMesh& sheets) {
  Reference original(input), cut(sheets);
  const double diagonal = [&] {
    Vec3 lo = input.positions[0], hi = lo;
    for (const Vec3& p : input.positions) {
      lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
      hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
    }
    return double(length(hi - lo));
  }();
  double worst = 0;
  int samples = 0;
  for (int f = 0; f < input.faceCount(); ++f) {
    const int subFaces = input.faceSizes[f] == 4 ? 1 : input.faceSizes[f];
    for (int sub = 0; sub < subFaces; ++sub) {
      for (double u : {0.0, 0.3, 0.5, 1.0}) {
        for (double v : {0.0, 0.7, 1.0}) {
          Vec3d a, b;
          if (!original.evaluateFace(f, subFaces == 1 ? -1 : sub, u, v, a)) continue;  // a hole
          ASSERT_TRUE(cut.evaluateFace(f, subFaces == 1 ? -1 : sub, u, v, b)) << "face " << f;
          worst = std::max(worst, length(a - b));
          ++samples;
        }
      }
    }
  }
  EXPECT_GT(samples, 0);
  EXPECT_LE(worst, 1e-6 * diagonal) << samples << " samples";
}

TEST(ManifoldSheets, SheetsHaveTheInputsLimitSurface) {
  int checked = 0;
  for (const std::string& path : testing::openSubdivShapes()) {
    ControlMesh mesh;
    try {
      mesh = readObjFile(path);
    } catch (const TesseraError&) {
      continue;
    }
    const ManifoldSheets cut = cutIntoSheets(mesh);
    if (!cut.cut()) continue;
    SCOPED_TRACE(testing::baseName(path));
    ++checked;
    if (testing::baseName(path).find("val2") != std::string::npos) {
      expectSameLimitSurface<testing::FarPatchReference>(mesh, cut.sheets);
    } else {
      expectSameLimitSurface<testing::BfrReference>(mesh, cut.sheets);
    }
  }
  EXPECT_GE(checked, 5);
}

// The same fins with an infinitely sharp crease across vertex 1 in one fin: three sharp edges
// make vertex 1 a corner in OpenSubdiv at every level, so every copy is one; each fin's copy sees
// only two of them (the crease rule) and the sheets' surface would not be the input's. (Bfr as
// the reference: Far's Gregory end caps at this corner differ by 4e-4 between the two meshes.)
TEST(ManifoldSheets, InteriorNonManifoldCreaseWithAThirdSharpEdgeIsACorner) {
  ControlMesh mesh = threeFinsOnAChain();
  mesh.creases.push_back({1, 4, kInfiniteSharpness});
  const ManifoldSheets cut = cutIntoSheets(mesh);
  expectSheetsOfInput(cut, mesh);
  for (int s : copiesOf(cut, 1)) EXPECT_EQ(cornerSharpness(cut.sheets, s), kInfiniteSharpness);
  EXPECT_EQ(cornerSharpness(cut.seams, 1), kInfiniteSharpness);
  expectSameLimitSurface<testing::BfrReference>(mesh, cut.sheets);
}

}  // namespace
}  // namespace tessera
