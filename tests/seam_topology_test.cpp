// SeamTopology's pinched corners, by hand: where a tile must keep a point inside (a valence-2
// vertex between two faces; a face folding back along the edge it left by; an edge collapsed to
// its vertex), and nowhere else.
#include "core/surface/seam_topology.h"

#include <gtest/gtest.h>

namespace tessera {
namespace {

ControlMesh meshOf(std::vector<std::vector<int>> faces, int vertices) {
  ControlMesh mesh;
  for (int v = 0; v < vertices; ++v) mesh.positions.emplace_back(float(v), float(v * v % 7), float(v % 3));
  for (const auto& face : faces) {
    mesh.faceSizes.push_back(int(face.size()));
    mesh.faceVertices.insert(mesh.faceVertices.end(), face.begin(), face.end());
  }
  return mesh;
}

std::vector<bool> pinchedCorners(const SeamTopology& seams, int face) {
  std::vector<bool> out;
  for (int k = 0; k < seams.faceSizes[face]; ++k) out.push_back(seams.pinched(face, k));
  return out;
}

TEST(SeamTopology, AQuadMeshHasNoPinchedCorner) {
  // Two quads side by side: no corner is pinched.
  const SeamTopology seams(meshOf({{0, 1, 4, 3}, {1, 2, 5, 4}}, 6));
  EXPECT_EQ(pinchedCorners(seams, 0), std::vector<bool>(4, false));
  EXPECT_EQ(pinchedCorners(seams, 1), std::vector<bool>(4, false));
}

TEST(SeamTopology, AFaceFoldingBackAlongAnEdgeIsPinchedThere) {
  // "0 1 0 2": at corner 1 the face goes 0 → 1 → 0, at corner 3 it goes 0 → 2 → 0; at corners
  // 0 and 2 (vertex 0) its two edges differ.
  const SeamTopology seams(meshOf({{0, 1, 0, 2}}, 3));
  EXPECT_EQ(pinchedCorners(seams, 0), (std::vector<bool>{false, true, false, true}));
}

TEST(SeamTopology, AnEdgeCollapsedToItsVertexPinchesBothItsCorners) {
  const SeamTopology seams(meshOf({{0, 0, 1, 2}}, 3));
  EXPECT_EQ(pinchedCorners(seams, 0), (std::vector<bool>{true, true, false, false}));
}

TEST(SeamTopology, AValence2VertexBetweenTwoFacesIsPinched) {
  // Two quads sharing edges {0,1} and {1,2}: vertex 1 has two edges, both shared by the same two
  // faces.
  const SeamTopology seams(meshOf({{0, 1, 2, 3}, {2, 1, 0, 4}}, 5));
  EXPECT_EQ(pinchedCorners(seams, 0), (std::vector<bool>{false, true, false, false}));
  EXPECT_EQ(pinchedCorners(seams, 1), (std::vector<bool>{false, true, false, false}));
}

}  // namespace
}  // namespace tessera
