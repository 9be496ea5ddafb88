// The CER operators recover a ring's connectivity from indices alone: checked against the
// topology OpenSubdiv Far builds for the same ring mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/rings/cer_layout.h"
#include "core/topology/far_topology.h"
#include "reference/ring_meshes.h"

namespace tessera {
namespace {

std::set<int> asSet(const cer::PackedIndices& p, int count) {
  std::set<int> s;
  for (int k = 0; k < count; ++k) s.insert(p[k]);
  return s;
}

void expectOperatorsMatchFar(const cer::RingShape& shape) {
  SCOPED_TRACE("valence " + std::to_string(shape.sectors) + (shape.open ? " open" : ""));
  ControlMesh mesh = testing::makeRingMesh(shape, 11);
  auto refiner = createTopologyRefiner(mesh);
  const auto& level = refiner->GetLevel(0);
  // Faces: the mesh's faces are numbered 4i + k exactly like the operators'.
  for (int f = 0; f < 4 * shape.sectors; ++f) {
    auto vertices = level.GetFaceVertices(f);
    cer::PackedIndices mine = cer::vertexF(shape, f);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(mine[k], vertices[k]) << "face " << f;
  }
  const int edges = 6 * shape.sectors + (shape.open ? 2 : 0);
  for (int e = 0; e < edges; ++e) {
    cer::PackedIndices ends = cer::vertexE(shape, e);
    Far::Index edge = level.FindEdge(ends[0], ends[1]);
    ASSERT_GE(edge, 0) << "edge " << e << " is not an edge of the mesh";
    auto farFaces = level.GetEdgeFaces(edge);
    if (farFaces.size() == 2) {
      EXPECT_EQ(asSet(cer::faceE(shape, e), 2), std::set<int>(farFaces.begin(), farFaces.end())) << "edge " << e;
    }
  }
  for (int j = 1; j <= 2 * shape.sectors; ++j) {
    Far::Index v = cer::ringIndexOfVertex(j);
    if (level.IsVertexBoundary(v)) continue;  // the boundary spokes of an open ring
    auto farNeighbours = level.GetVertexEdges(v);
    std::set<int> expected;
    for (Far::Index edge : farNeighbours) {
      auto ends = level.GetEdgeVertices(edge);
      expected.insert(ends[0] == v ? ends[1] : ends[0]);
    }
    EXPECT_EQ(asSet(cer::vertexV(shape, j), 4), expected) << "vertex " << j;
    auto farFaces = level.GetVertexFaces(v);
    EXPECT_EQ(asSet(cer::faceV(shape, j), 4), std::set<int>(farFaces.begin(), farFaces.end())) << "vertex " << j;
  }
}

TEST(CerLayout, OperatorsRecoverFarsConnectivity) {
  for (int n : {3, 5, 8, 21, 22, 64}) expectOperatorsMatchFar({n, false});
  for (int k : {2, 3, 6}) expectOperatorsMatchFar({k, true});
}

TEST(CerLayout, IndicesAreEightBitUpToValenceTwentyOneAndSixteenBitBeyond) {
  EXPECT_EQ(cer::indexBits({21, false}), 8);
  EXPECT_EQ(cer::RingShape({21, false}).refinedPointCount(), 253);
  EXPECT_EQ(cer::indexBits({22, false}), 16);
  // The largest index of a valence-21 refined set still fits its 8-bit lane.
  cer::RingShape shape{21, false};
  cer::PackedIndices p = cer::pack(shape, 252, 251, 250, 249);
  EXPECT_EQ(p[0], 252);
  EXPECT_EQ(p[3], 249);
}

}  // namespace
}  // namespace tessera
