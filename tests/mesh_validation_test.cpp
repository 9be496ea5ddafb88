// validateControlMesh: a valid cube passes, and each broken invariant is refused with the kind and
// the element index the message promises.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/base/error.h"
#include "core/mesh/control_mesh.h"

namespace tessera {
namespace {

// The unit cube with outward, counter-clockwise quads (vertex i has coordinates from its bits).
ControlMesh makeCube() {
  ControlMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.positions.emplace_back(float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1));
  }
  mesh.faceSizes = {4, 4, 4, 4, 4, 4};
  mesh.faceVertices = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  return mesh;
}

// Expects validation to fail with `kind` and a message containing `part`.
void expectRefused(const ControlMesh& mesh, ErrorKind kind, const std::string& part,
                   const MeshLimits& limits = {}) {
  try {
    validateControlMesh(mesh, limits);
    ADD_FAILURE() << "accepted; expected: " << part;
  } catch (const TesseraError& error) {
    EXPECT_EQ(error.kind(), kind) << error.what();
    EXPECT_NE(std::string(error.what()).find(part), std::string::npos)
        << "message: " << error.what() << "\nexpected to contain: " << part;
  }
}

TEST(MeshValidation, CubeWithTagsPasses) {
  ControlMesh mesh = makeCube();
  mesh.creases = {{0, 1, 2.0f}, {3, 1, kInfiniteSharpness}, {7, 5, 100.0f}};  // either direction
  mesh.corners = {{6, 0.0f}};
  mesh.holes = {2, 5};
  mesh.positions.emplace_back(9.0f, 9.0f, 9.0f);  // used by no face
  EXPECT_NO_THROW(validateControlMesh(mesh));
}

TEST(MeshValidation, MeshWithoutFacesIsInvalid) {
  ControlMesh mesh;
  expectRefused(mesh, ErrorKind::kInvalidInput, "the mesh has no faces");
  mesh.positions.emplace_back(0.0f, 0.0f, 0.0f);
  expectRefused(mesh, ErrorKind::kInvalidInput, "the mesh has no faces");
}

TEST(MeshValidation, CountsPastTheLimitsAreRefused) {
  MeshLimits limits;
  limits.maxVertices = 7;
  expectRefused(makeCube(), ErrorKind::kLimitExceeded, "8 vertices; the limit is 7", limits);
  limits = {};
  limits.maxFaces = 5;
  expectRefused(makeCube(), ErrorKind::kLimitExceeded, "6 faces; the limit is 5", limits);
  limits = {};
  limits.maxFaceSize = 3;
  expectRefused(makeCube(), ErrorKind::kLimitExceeded, "face 0 has 4 vertices; the limit is 3",
                limits);
}

TEST(MeshValidation, FacesNeedThreeVertices) {
  ControlMesh mesh = makeCube();
  mesh.faceSizes = {4, 4, 2, 6, 4, 4};
  expectRefused(mesh, ErrorKind::kInvalidInput, "face 2 has 2 vertices");
  mesh.faceSizes = {4, 4, -1, 9, 4, 4};
  expectRefused(mesh, ErrorKind::kInvalidInput, "face 2 has -1 vertices");
}

TEST(MeshValidation, FaceSizesMustAddUpToTheFaceVertices) {
  ControlMesh mesh = makeCube();
  mesh.faceVertices.pop_back();
  expectRefused(mesh, ErrorKind::kInvalidInput, "add up to 24 face vertices, but 23 are given");
}

TEST(MeshValidation, FaceVertexIndicesMustBeInRange) {
  ControlMesh mesh = makeCube();
  mesh.faceVertices[9] = 8;  // face 2
  expectRefused(mesh, ErrorKind::kInvalidInput, "face 2 refers to vertex 8, but the mesh has 8");
  mesh.faceVertices[9] = -1;
  expectRefused(mesh, ErrorKind::kInvalidInput, "face 2 refers to vertex -1");
}

// OpenSubdiv evaluates faces that repeat a vertex (its catmark_nonman_* shapes): they pass.
TEST(MeshValidation, FaceMayRepeatAVertex) {
  ControlMesh mesh = makeCube();
  mesh.faceVertices[15] = 6;  // face 3 (2 6 7 3) becomes 2 6 7 6
  EXPECT_NO_THROW(validateControlMesh(mesh));
  mesh.faceVertices[12] = mesh.faceVertices[13] = mesh.faceVertices[14] = 6;  // 6 6 6 6
  EXPECT_NO_THROW(validateControlMesh(mesh));
}

TEST(MeshValidation, CoordinatesMustBeFiniteAndWithinTheLimit) {
  ControlMesh mesh = makeCube();
  mesh.positions[3].y = std::numeric_limits<float>::quiet_NaN();
  expectRefused(mesh, ErrorKind::kInvalidInput, "vertex 3 has a coordinate that is not finite");
  mesh.positions[3].y = -std::numeric_limits<float>::infinity();
  expectRefused(mesh, ErrorKind::kInvalidInput, "vertex 3 has a coordinate that is not finite");
  mesh.positions[3].y = 2e18f;
  expectRefused(mesh, ErrorKind::kLimitExceeded, "vertex 3 has coordinate 2e+18");
  mesh.positions[3].y = -1e18f;
  EXPECT_NO_THROW(validateControlMesh(mesh));
}

// A mesh whose box is a point has no scale for a tolerance: refused by name, not left for the
// first tessellation to fail on. Flat meshes and a single pair of distinct points are boxes.
TEST(MeshValidation, AMeshWhoseVerticesAllCoincideIsRefused) {
  ControlMesh mesh = makeCube();
  for (Vec3& p : mesh.positions) p = Vec3(1.0f, 1.0f, 1.0f);
  expectRefused(mesh, ErrorKind::kInvalidInput, "all 8 vertices coincide at (1, 1, 1): the mesh has an empty bounding box");
  mesh.positions[5].z = 1.0f + 1e-6f;  // one vertex apart is a box (a thin one)
  EXPECT_NO_THROW(validateControlMesh(mesh));

  ControlMesh point;
  point.positions = {Vec3(0.0f, 0.0f, 0.0f)};
  point.faceSizes = {3};
  point.faceVertices = {0, 0, 0};
  expectRefused(point, ErrorKind::kInvalidInput, "the mesh's one vertex is at (0, 0, 0): the mesh has an empty bounding box");

  ControlMesh far = point;  // named where the user put it, not relative to the origin kept aside
  far.origin = Vec3d(1e6, 0, 0);
  expectRefused(far, ErrorKind::kInvalidInput, "the mesh's one vertex is at (1e+06, 0, 0)");

  ControlMesh flat = makeCube();
  for (Vec3& p : flat.positions) p.z = 0.0f;  // a square, every face folded onto it
  EXPECT_NO_THROW(validateControlMesh(flat));
}

TEST(MeshValidation, CreasesMustJoinTwoVerticesOfAFaceEdge) {
  ControlMesh mesh = makeCube();
  mesh.creases = {{0, 1, 1.0f}, {0, 8, 1.0f}};
  expectRefused(mesh, ErrorKind::kInvalidInput, "crease 1 refers to vertex 8");
  mesh.creases = {{0, 1, 1.0f}, {-2, 1, 1.0f}};
  expectRefused(mesh, ErrorKind::kInvalidInput, "crease 1 refers to vertex -2");
  mesh.creases = {{4, 4, 1.0f}};
  expectRefused(mesh, ErrorKind::kInvalidInput, "crease 0 joins vertex 4 to itself");
  mesh.creases = {{0, 1, 1.0f}, {0, 3, 1.0f}};  // a face diagonal
  expectRefused(mesh, ErrorKind::kInvalidInput, "crease 1 (0, 3) is not an edge of any face");
  mesh.creases = {{0, 7, 1.0f}};  // the cube's main diagonal
  expectRefused(mesh, ErrorKind::kInvalidInput, "crease 0 (0, 7) is not an edge of any face");
}

TEST(MeshValidation, SharpnessMustBeFiniteAndNotNegative) {
  ControlMesh mesh = makeCube();
  mesh.creases = {{0, 1, -0.5f}};
  expectRefused(mesh, ErrorKind::kInvalidInput, "crease 0 has sharpness -0.5");
  mesh.creases = {{0, 1, std::nanf("")}};
  expectRefused(mesh, ErrorKind::kInvalidInput, "crease 0 has sharpness nan");
  mesh.creases = {{0, 1, std::numeric_limits<float>::infinity()}};
  expectRefused(mesh, ErrorKind::kInvalidInput, "crease 0 has sharpness inf");
  mesh.creases = {};
  mesh.corners = {{1, 1.0f}, {2, -3.0f}};
  expectRefused(mesh, ErrorKind::kInvalidInput, "corner 1 has sharpness -3");
}

TEST(MeshValidation, AnEdgeOrVertexTaggedTwiceMustSayOneSharpness) {
  ControlMesh mesh = makeCube();
  mesh.creases = {{0, 1, 2.0f}, {2, 3, 1.0f}, {1, 0, 2.0f}};  // the same edge twice, alike: accepted
  validateControlMesh(mesh);
  mesh.creases = {{0, 1, 2.0f}, {2, 3, 1.0f}, {1, 0, 5.0f}};
  expectRefused(mesh, ErrorKind::kInvalidInput, "creases 0 and 2 both tag edge (0, 1), with sharpness 2 and 5");
  mesh.creases = {};
  mesh.corners = {{3, 1.0f}, {5, 2.0f}, {3, 0.5f}};
  expectRefused(mesh, ErrorKind::kInvalidInput, "corners 0 and 2 both tag vertex 3, with sharpness 1 and 0.5");
}

// A fan of triangles around one vertex: `faces` faces at vertex 0.
ControlMesh fan(int faces) {
  ControlMesh mesh;
  mesh.positions.push_back(Vec3(0, 0, 0));
  for (int i = 0; i < faces; ++i) {
    const double angle = 6.283185307179586 * i / faces;
    mesh.positions.push_back(Vec3(float(std::cos(angle)), float(std::sin(angle)), 0));
  }
  for (int i = 0; i < faces; ++i) {
    mesh.faceSizes.push_back(3);
    mesh.faceVertices.insert(mesh.faceVertices.end(), {0, 1 + i, 1 + (i + 1) % faces});
  }
  return mesh;
}

TEST(MeshValidation, AVertexInMoreFacesThanOpenSubdivHoldsIsRefusedNamingIt) {
  validateControlMesh(fan(65535));
  expectRefused(fan(65536), ErrorKind::kInvalidInput, "vertex 0 is shared by more than 65535 faces");
  MeshLimits limits;
  limits.maxValence = 16;
  expectRefused(fan(17), ErrorKind::kInvalidInput, "vertex 0 is shared by more than 16 faces", limits);
}

TEST(MeshValidation, CornersAndHolesMustBeInRange) {
  ControlMesh mesh = makeCube();
  mesh.corners = {{8, 1.0f}};
  expectRefused(mesh, ErrorKind::kInvalidInput, "corner 0 refers to vertex 8");
  mesh.corners = {};
  mesh.holes = {0, 6};
  expectRefused(mesh, ErrorKind::kInvalidInput, "hole 1 refers to face 6, but the mesh has 6");
  mesh.holes = {-1};
  expectRefused(mesh, ErrorKind::kInvalidInput, "hole 0 refers to face -1");
}

TEST(MeshValidation, HolesMustBeUnique) {
  ControlMesh mesh = makeCube();
  mesh.holes = {3, 1, 3};
  expectRefused(mesh, ErrorKind::kInvalidInput, "hole 2 lists face 3, which is already a hole");
}

}  // namespace
}  // namespace tessera
