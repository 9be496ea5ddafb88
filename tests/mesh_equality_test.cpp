// tests/support/mesh_equality.h, which the bit-for-bit comparisons of other tests rely on: equal
// meshes compare equal, and one changed bit anywhere is named by its array.
#include <gtest/gtest.h>

#include <cstring>

#include "tests/support/mesh_equality.h"

namespace tessera {
namespace {

TriangleMesh twoTriangles() {
  TriangleMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  mesh.normals.assign(4, Vec3(0, 0, 1));
  mesh.indices = {0, 1, 2, 0, 2, 3};
  mesh.vertexFace.assign(4, 0);
  mesh.vertexSubFace.assign(4, -1);
  mesh.vertexUv = {0, 0, 1, 0, 1, 1, 0, 1};
  mesh.vertexPoint = {0, 1, 2, 3};
  mesh.trianglePiece = {0, 0};
  mesh.triangleST = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
  mesh.triangleFace = {0, 0};
  mesh.triangleSubFace = {-1, -1};
  return mesh;
}

TEST(MeshEquality, NamesTheFirstArrayWhereOneBitDiffers) {
  EXPECT_EQ(testing::meshDifference(twoTriangles(), twoTriangles()), "");
  auto flipped = [](const auto& values, const char* name) {
    TriangleMesh mesh = twoTriangles();
    auto& array = values(mesh);
    unsigned char byte;
    std::memcpy(&byte, array.data(), 1);
    byte ^= 1;
    std::memcpy(array.data(), &byte, 1);
    EXPECT_EQ(testing::meshDifference(mesh, twoTriangles()), name);
  };
  flipped([](TriangleMesh& m) -> auto& { return m.positions; }, "positions");
  flipped([](TriangleMesh& m) -> auto& { return m.normals; }, "normals");
  flipped([](TriangleMesh& m) -> auto& { return m.indices; }, "indices");
  flipped([](TriangleMesh& m) -> auto& { return m.vertexUv; }, "vertexUv");
  flipped([](TriangleMesh& m) -> auto& { return m.vertexPoint; }, "vertexPoint");
  flipped([](TriangleMesh& m) -> auto& { return m.triangleST; }, "triangleST");
  flipped([](TriangleMesh& m) -> auto& { return m.triangleSubFace; }, "triangleSubFace");
  TriangleMesh shorter = twoTriangles();
  shorter.indices.resize(3);
  EXPECT_EQ(testing::meshDifference(shorter, twoTriangles()), "indices");
  TriangleMesh negativeZero = twoTriangles();
  negativeZero.positions[0].x = -0.0f;  // equal as numbers, not as bits
  EXPECT_EQ(testing::meshDifference(negativeZero, twoTriangles()), "positions");
}

}  // namespace
}  // namespace tessera
