// GLB output: index width chosen by vertex count, exact round trip through readGlb (tinygltf,
// tests/support/glb_reader.h), files that Khronos glTF-Validator accepts on both sides of the
// 16-bit limit, and clear refusals of GLBs readGlb cannot trust.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "core/base/error.h"
#include "core/output/glb_writer.h"
#include "tests/support/glb_reader.h"
#include "tests/support/gltf_validator.h"

namespace tessera {
namespace {

// A flat strip of quads, two triangles each, with `vertexCount` vertices (even).
TriangleMesh strip(size_t vertexCount) {
  TriangleMesh mesh;
  const size_t columns = vertexCount / 2;
  for (size_t row = 0; row < 2; ++row) {
    for (size_t c = 0; c < columns; ++c) {
      mesh.positions.push_back(Vec3(float(c) * 0.01f, float(row), 0.0f));
      mesh.normals.push_back(Vec3(0, 0, 1));
    }
  }
  for (uint32_t c = 0; c + 1 < columns; ++c) {
    const uint32_t a = c, b = c + 1, d = uint32_t(columns) + c, e = d + 1;
    mesh.indices.insert(mesh.indices.end(), {a, b, e, a, e, d});
  }
  return mesh;
}

std::string jsonChunk(const std::vector<uint8_t>& glb) {
  uint32_t length = 0;
  std::memcpy(&length, glb.data() + 12, 4);
  return std::string(reinterpret_cast<const char*>(glb.data()) + 20, length);
}

void expectSameMesh(const TriangleMesh& back, const TriangleMesh& mesh) {
  ASSERT_EQ(back.positions.size(), mesh.positions.size());
  EXPECT_EQ(back.indices, mesh.indices);
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    ASSERT_EQ(back.positions[v].x, mesh.positions[v].x);
    ASSERT_EQ(back.positions[v].y, mesh.positions[v].y);
    ASSERT_EQ(back.normals[v].z, mesh.normals[v].z);
  }
}

TEST(GlbWriter, UsesSixteenBitIndicesUpTo65535Vertices) {
  // 65535 is the primitive-restart value of 16-bit indices, so the last index allowed is 65534.
  for (size_t vertices : {size_t(8), size_t(65534)}) {
    TriangleMesh mesh = strip(vertices);
    std::vector<uint8_t> glb = writeGlb(mesh, {.description = {.sourceName = "strip"}});
    EXPECT_NE(jsonChunk(glb).find("\"componentType\":5123"), std::string::npos) << vertices;
    expectSameMesh(testing::readGlb(glb), mesh);
  }
}

TEST(GlbWriter, UsesThirtyTwoBitIndicesBeyond) {
  TriangleMesh mesh = strip(65536);
  std::vector<uint8_t> glb = writeGlb(mesh, {.description = {.sourceName = "strip"}});
  EXPECT_NE(jsonChunk(glb).find("\"componentType\":5125"), std::string::npos);
  expectSameMesh(testing::readGlb(glb), mesh);
}

TEST(GlbWriter, KhronosValidatorAcceptsBothIndexWidths) {
  // 65534 vertices: 16-bit indices whose byte length is not a multiple of 4 (padding checked).
  for (size_t vertices : {size_t(10), size_t(65534), size_t(70000)}) {
    testing::ValidatorReport validation =
        testing::validateGlb(writeGlb(strip(vertices), {.description = {.sourceName = "strip"}}), "strip-" + std::to_string(vertices));
    ASSERT_TRUE(validation.ran) << "glTF-Validator did not run (npm install in tests/gltf?): "
                                << validation.report;
    EXPECT_TRUE(validation.clean()) << vertices << " vertices: " << validation.report;
  }
}

void expectRefused(const std::vector<uint8_t>& glb, const std::string& message) {
  try {
    testing::readGlb(glb);
    FAIL() << "expected a refusal mentioning \"" << message << "\"";
  } catch (const TesseraError& error) {
    EXPECT_NE(std::string(error.what()).find(message), std::string::npos) << error.what();
  }
}

TEST(GlbWriter, ReadGlbRefusesWhatItCannotTrust) {
  std::vector<uint8_t> glb = writeGlb(strip(8), {.description = {.sourceName = "strip"}});
  expectRefused({}, "not a readable GLB");
  expectRefused(std::vector<uint8_t>(glb.begin(), glb.begin() + glb.size() / 2), "not a readable GLB");
  TriangleMesh dangling = strip(8);
  dangling.indices.back() = 8;  // one past the last vertex
  expectRefused(writeGlb(dangling, {.description = {.sourceName = "strip"}}), "GLB index 8 has no vertex");
}

}  // namespace
}  // namespace tessera
