// The three GLB encodings end to end on a real mesh: each file is accepted by Khronos
// glTF-Validator, decodes (meshoptimizer's decoder, the node's translation and scale applied in
// float as a viewer does) to a closed mesh whose measured two-sided distance to OpenSubdiv's limit
// surface is within ε, and states in asset.extras what it promises. Quantization too coarse for
// ε is refused (quantized) or left out (meshopt).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <tuple>

#include "core/pipeline/preprocessing.h"
#include "core/base/error.h"
#include "core/pipeline/glb_output.h"
#include "core/mesh/mesh_codec.h"
#include "core/mesh/obj_reader.h"
#include "core/base/sha256.h"
#include "core/base/version.h"
#include "tests/support/glb_reader.h"
#include "tests/support/gltf_validator.h"
#include "reference/limit_distance.h"
#include "reference/models.h"

namespace tessera {
namespace {

nlohmann::json jsonOf(const std::vector<uint8_t>& glb) {
  uint32_t length = 0;
  std::memcpy(&length, glb.data() + 12, 4);
  return nlohmann::json::parse(std::string(reinterpret_cast<const char*>(glb.data()) + 20, length));
}

// Edges (by the bit patterns of their end points) used by other than exactly two triangles.
size_t unpairedEdges(const TriangleMesh& mesh) {
  using Point = std::tuple<float, float, float>;
  auto point = [&](uint32_t v) {
    return Point{mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z};
  };
  std::map<std::pair<Point, Point>, int> uses;
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    for (int k = 0; k < 3; ++k) {
      Point a = point(mesh.indices[t + k]), b = point(mesh.indices[t + (k + 1) % 3]);
      ++uses[std::minmax(a, b)];
    }
  }
  size_t unpaired = 0;
  for (const auto& [edge, count] : uses) unpaired += count != 2;
  return unpaired;
}

struct Encoded {
  std::vector<uint8_t> glb;
  TessellationSummary summary;
};

Encoded encode(const ControlMesh& mesh, const PatchSet& patches, double relative,
               GlbEncoding encoding) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(relative);
  const auto positions = reserveForEncoding(encoding, patches, options);
  const TessellationResult result = tessellate(patches, mesh, options);
  const GlbRequest request{encoding, "torus", sha256Hex(encodeCanonicalMesh(mesh))};
  return {writeGlb(result.mesh, glbOptionsFor(request, options, result.summary, positions)),
          result.summary};
}

TEST(GlbEncoding, EveryEncodingDecodesWithinToleranceClosedAndValid) {
  const ControlMesh mesh =
      readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_torus_creases0.obj");
  const PatchSet patches = buildPatchSet(mesh);
  const testing::LimitSurface surface(mesh);
  // At 1e-4 of the diagonal the 16-bit grid's error is about a tenth of ε, so it shows.
  constexpr double kRelative = 1e-4;
  size_t floatBytes = 0;
  for (GlbEncoding encoding :
       {GlbEncoding::kFloat, GlbEncoding::kQuantized, GlbEncoding::kMeshopt}) {
    SCOPED_TRACE(glbEncodingName(encoding));
    const Encoded encoded = encode(mesh, patches, kRelative, encoding);
    const testing::ValidatorReport validation =
        testing::validateGlb(encoded.glb, std::string("torus-") + glbEncodingName(encoding));
    ASSERT_TRUE(validation.ran) << validation.report;
    EXPECT_TRUE(validation.clean()) << validation.report;

    const TriangleMesh back = testing::readGlb(encoded.glb);
    EXPECT_EQ(int64_t(back.triangleCount()), encoded.summary.triangles);
    EXPECT_EQ(unpairedEdges(back), 0u);
    const testing::LimitDistanceReport report =
        measureLimitDistance(surface, testing::viewOf(back));
    EXPECT_LE(report.twoSidedRelative(), kRelative + testing::LimitSurface::kRelativeAccuracy);
    EXPECT_LE(encoded.summary.guaranteedBound, encoded.summary.tolerance);

    const nlohmann::json json = jsonOf(encoded.glb);
    const nlohmann::json& extras = json["asset"]["extras"];
    EXPECT_EQ(json["asset"]["generator"], std::string("Tessera ") + kVersion);
    EXPECT_EQ(extras["encoding"], glbEncodingName(encoding));
    EXPECT_EQ(extras["source"]["name"], "torus");
    EXPECT_EQ(extras["source"]["sha256"], sha256Hex(encodeCanonicalMesh(mesh)));
    EXPECT_DOUBLE_EQ(extras["tolerance"].get<double>(), encoded.summary.tolerance);
    EXPECT_DOUBLE_EQ(extras["guaranteedBound"].get<double>(), encoded.summary.guaranteedBound);
    if (encoding == GlbEncoding::kFloat) {
      floatBytes = encoded.glb.size();
      EXPECT_FALSE(extras.contains("positionError"));
    } else {
      // The grid's error was set aside: a share of ε, inside the bound the file states.
      const double error = extras["positionError"].get<double>();
      EXPECT_GT(error, 0);
      EXPECT_LE(error, kQuantizationShare * encoded.summary.tolerance);
      EXPECT_LT(encoded.glb.size(), floatBytes);
      std::printf(
          "%-9s %8zu bytes (%.2f of float), position error %.3g of eps, measured %.2f of eps\n",
          glbEncodingName(encoding), encoded.glb.size(),
          double(encoded.glb.size()) / double(floatBytes), error / encoded.summary.tolerance,
          report.twoSidedRelative() / kRelative);
    }
  }
}

// Each triangle as its corners' positions (bit patterns), rotated to start at the least corner
// (the winding kept: meshoptimizer's index codec may rotate a triangle's corners), all sorted.
std::vector<std::array<float, 9>> canonicalTriangles(const TriangleMesh& mesh) {
  std::vector<std::array<float, 9>> triangles(mesh.triangleCount());
  for (size_t t = 0; t < triangles.size(); ++t) {
    std::array<std::array<float, 3>, 3> corner;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.positions[mesh.indices[3 * t + k]];
      corner[k] = {p.x, p.y, p.z};
    }
    const int first = int(std::min_element(corner.begin(), corner.end()) - corner.begin());
    for (int k = 0; k < 3; ++k) std::copy_n(corner[(first + k) % 3].begin(), 3, triangles[t].begin() + 3 * k);
  }
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

// Past 512K triangles the meshopt encoding orders the triangles for the vertex cache in runs,
// with a checkpoint between them (glb_writer.cpp): the file still holds exactly the triangles of
// the float file of the same mesh (float positions: the grid is too coarse at 1e-6 of the
// diagonal), and Khronos glTF-Validator accepts it.
TEST(GlbEncoding, AMeshoptFileOrderedInRunsHoldsTheSameTriangles) {
  const ControlMesh mesh = readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_cube.obj");
  TessellationOptions options;
  options.accuracy = Accuracy::relative(1e-6);
  PreprocessingOptions preprocessing;
  preprocessing.finestRelativeTolerance = finestRelativeTolerance(mesh, options);
  const PatchSet patches = buildPatchSet(mesh, preprocessing);
  const TessellationResult result = tessellate(patches, mesh, options);
  ASSERT_GT(result.summary.triangles, 3 * 512 * 1024) << "fewer triangles than three runs";
  GlbOptions glb;
  glb.description.sourceName = "cube";
  const std::vector<uint8_t> plain = writeGlb(result.mesh, glb);
  glb.encoding = GlbEncoding::kMeshopt;
  const std::vector<uint8_t> compressed = writeGlb(result.mesh, glb);
  const testing::ValidatorReport validation = testing::validateGlb(compressed, "cube-meshopt-runs");
  ASSERT_TRUE(validation.ran) << validation.report;
  EXPECT_TRUE(validation.clean()) << validation.report;
  const TriangleMesh back = testing::readGlb(compressed);
  ASSERT_EQ(int64_t(back.triangleCount()), result.summary.triangles);
  EXPECT_TRUE(canonicalTriangles(back) == canonicalTriangles(testing::readGlb(plain)));
  EXPECT_LT(compressed.size(), plain.size() / 2);
}

// A view whose codec would read more than 64 MiB is stored as it is beside the compressed ones
// (glb_writer.cpp: meshoptimizer's codecs cannot stop for a cancelled call): a flat grid of 5.9M
// triangles keeps its 32-bit indices (70 MB) uncompressed and its positions and normals
// compressed; the file validates and holds the float file's triangles.
TEST(GlbEncoding, AMeshoptFileKeepsAViewTooLargeForTheCodecsUncompressed) {
  constexpr uint32_t kCells = 1710;  // 2 · 1710² triangles: indices past 64 MiB
  TriangleMesh grid;
  for (uint32_t j = 0; j <= kCells; ++j) {
    for (uint32_t i = 0; i <= kCells; ++i) {
      grid.positions.push_back(Vec3(float(i) / kCells, float(j) / kCells, 0.0f));
      grid.normals.push_back(Vec3(0.0f, 0.0f, 1.0f));
    }
  }
  for (uint32_t j = 0; j < kCells; ++j) {
    for (uint32_t i = 0; i < kCells; ++i) {
      const uint32_t a = j * (kCells + 1) + i, b = a + 1, c = a + kCells + 1, d = c + 1;
      grid.indices.insert(grid.indices.end(), {a, b, d, a, d, c});
    }
  }
  GlbOptions glb;
  glb.description.sourceName = "grid";
  const std::vector<uint8_t> plain = writeGlb(grid, glb);
  glb.encoding = GlbEncoding::kMeshopt;
  const std::vector<uint8_t> compressed = writeGlb(grid, glb);
  const nlohmann::json json = jsonOf(compressed);
  std::vector<bool> viewCompressed;
  for (const nlohmann::json& view : json["bufferViews"]) viewCompressed.push_back(view.contains("extensions"));
  EXPECT_EQ(viewCompressed, (std::vector<bool>{true, true, false})) << "positions, normals, indices";
  const testing::ValidatorReport validation = testing::validateGlb(compressed, "grid-meshopt-mixed");
  ASSERT_TRUE(validation.ran) << validation.report;
  EXPECT_TRUE(validation.clean()) << validation.report;
  const TriangleMesh back = testing::readGlb(compressed);
  ASSERT_EQ(back.triangleCount(), grid.triangleCount());
  EXPECT_TRUE(canonicalTriangles(back) == canonicalTriangles(testing::readGlb(plain)));
}

TEST(GlbEncoding, AGridTooCoarseForTheToleranceIsRefusedOrLeftOut) {
  const ControlMesh mesh =
      readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_torus_creases0.obj");
  const PatchSet patches = buildPatchSet(mesh);
  TessellationOptions options;
  options.accuracy = Accuracy::relative(1e-5);  // about the 16-bit grid's own error over the box
  try {
    reserveForEncoding(GlbEncoding::kQuantized, patches, options);
    FAIL() << "quantized positions accepted at 1e-5 of the diagonal";
  } catch (const TesseraError& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kInvalidInput);
    EXPECT_NE(std::string(error.what()).find("quantized positions move vertices"),
              std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(reserveForEncoding(GlbEncoding::kMeshopt, patches, options).has_value());
  EXPECT_EQ(options.encodingReserve, 0.0);
  // A uniform level meets no ε: the grid is always used and its error added to the bound.
  options.accuracy = Accuracy::uniformLevel(2);
  EXPECT_TRUE(reserveForEncoding(GlbEncoding::kQuantized, patches, options).has_value());
  EXPECT_GT(options.encodingReserve, 0.0);
}

}  // namespace
}  // namespace tessera
