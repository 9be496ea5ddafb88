// Texture coordinates (face-varying data) from the OBJ to the GLB: read as OBJ's vt, kept by the
// stores' encoding, evaluated on the limit surface as OpenSubdiv does for each of its
// FVarLinearInterpolation rules, split at UV seams with positions bit-identical, and written as
// TEXCOORD_0 in every GLB encoding.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/output/glb_writer.h"
#include "core/mesh/mesh_codec.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/mesh/subdivision_rules.h"
#include "core/pipeline/tessellate.h"
#include "reference/bfr_reference.h"
#include "tests/support/glb_reader.h"
#include "tests/support/gltf_validator.h"
#include "reference/models.h"

namespace tessera {
namespace {

constexpr UvInterpolation kEveryRule[] = {UvInterpolation::kAll,          UvInterpolation::kNone,
                                          UvInterpolation::kCornersOnly,  UvInterpolation::kCornersPlus1,
                                          UvInterpolation::kCornersPlus2, UvInterpolation::kBoundaries};

ControlMesh shape(const std::string& name) {
  return readObjFile(testing::modelsDir() + "/opensubdiv-shapes/" + name + ".obj");
}

// A pentagonal prism of our own: two pentagons (n-gons: Bfr's quad sub-faces) and five quads,
// unwrapped as a strip of the sides (one seam down a side edge) and the caps as islands of their
// own, with a crease round the top cap so sharp and seam copies meet.
ControlMesh texturedPrism() {
  std::string obj;
  for (int ring = 0; ring < 2; ++ring) {
    for (int k = 0; k < 5; ++k) {
      const double a = 2 * M_PI * k / 5;
      obj += "v " + std::to_string(std::cos(a)) + " " + std::to_string(ring * 1.5) + " " + std::to_string(-std::sin(a)) + "\n";
    }
  }
  for (int ring = 0; ring < 2; ++ring) {  // strip: vt 1..12
    for (int k = 0; k <= 5; ++k) obj += "vt " + std::to_string(k / 5.0) + " " + std::to_string(0.5 * ring) + "\n";
  }
  for (int cap = 0; cap < 2; ++cap) {  // caps: vt 13..17, 18..22
    for (int k = 0; k < 5; ++k) {
      const double a = 2 * M_PI * k / 5;
      obj += "vt " + std::to_string(0.25 + 0.5 * cap + 0.2 * std::cos(a)) + " " + std::to_string(0.75 + 0.2 * std::sin(a)) + "\n";
    }
  }
  for (int k = 0; k < 5; ++k) {
    const int a = k + 1, b = (k + 1) % 5 + 1;
    obj += "f " + std::to_string(a) + "/" + std::to_string(k + 1) + " " + std::to_string(b) + "/" + std::to_string(k + 2) + " " +
           std::to_string(b + 5) + "/" + std::to_string(k + 8) + " " + std::to_string(a + 5) + "/" + std::to_string(k + 7) + "\n";
  }
  obj += "f 1/13 5/17 4/16 3/15 2/14\n";
  obj += "f 6/18 7/19 8/20 9/21 10/22\n";
  for (int k = 0; k < 5; ++k) obj += "t crease 2/1/0 " + std::to_string(5 + k) + " " + std::to_string(5 + (k + 1) % 5) + " 10\n";
  return readObj(obj, "prism.obj");
}

TessellationResult tessellateAt(const ControlMesh& mesh, const PatchSet& patches, double relative) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(relative);
  options.recordParameters = true;
  return tessellate(patches, mesh, options);
}

// Under FVAR_LINEAR_ALL the UVs are the control polygon's, bilinear over each quad, and over an
// n-gon's quad sub-face k between corner k, the midpoints of edges k and k − 1 and the centroid of
// the face's UVs: derived by hand, not by OpenSubdiv.
std::array<double, 2> linearUv(const ControlMesh& mesh, int face, int subFace, double u, double v) {
  int first = 0;
  for (int f = 0; f < face; ++f) first += mesh.faceSizes[f];
  const int n = mesh.faceSizes[face];
  auto uv = [&](int k) {
    const int i = mesh.uvIndices[first + (k + n) % n];
    return std::array<double, 2>{mesh.uvs[2 * i], mesh.uvs[2 * i + 1]};
  };
  std::array<std::array<double, 2>, 4> c;
  if (subFace < 0) {
    c = {uv(0), uv(1), uv(2), uv(3)};
  } else {
    std::array<double, 2> centroid{0, 0};
    for (int k = 0; k < n; ++k) centroid[0] += uv(k)[0] / n, centroid[1] += uv(k)[1] / n;
    auto mid = [&](int a, int b) { return std::array<double, 2>{(uv(a)[0] + uv(b)[0]) / 2, (uv(a)[1] + uv(b)[1]) / 2}; };
    c = {uv(subFace), mid(subFace, subFace + 1), centroid, mid(subFace - 1, subFace)};
  }
  std::array<double, 2> r;
  for (int a = 0; a < 2; ++a) r[a] = (1 - u) * (1 - v) * c[0][a] + u * (1 - v) * c[1][a] + u * v * c[2][a] + (1 - u) * v * c[3][a];
  return r;
}

// Every triangle corner's UV against `reference` at the corner's own face parameter: a vertex
// shared across a seam with the wrong side's UV fails here.
template <typename Reference>
double worstCornerError(const TriangleMesh& m, Reference reference) {
  double worst = 0;
  for (size_t c = 0; c < m.indices.size(); ++c) {
    std::array<double, 2> expected;
    if (!reference(m.triangleFace[c / 3], m.triangleSubFace[c / 3], m.triangleST[2 * c], m.triangleST[2 * c + 1], expected)) continue;
    const uint32_t v = m.indices[c];
    worst = std::max({worst, std::abs(m.uvs[2 * v] - expected[0]), std::abs(m.uvs[2 * v + 1] - expected[1])});
  }
  return worst;
}

std::vector<std::pair<std::string, ControlMesh>> texturedMeshes() {
  std::vector<std::pair<std::string, ControlMesh>> meshes;
  for (const char* name : {"catmark_fvar_bound0", "catmark_fvar_bound1", "catmark_fvar_bound2", "catmark_fvar_bound3",
                           "catmark_fvar_bound4", "catmark_fvar_project0", "catmark_nonquads", "catmark_hole_test1",
                           "catmark_xord_interior", "catmark_smoothtris0"}) {
    meshes.emplace_back(name, shape(name));
  }
  meshes.emplace_back("prism", texturedPrism());
  return meshes;
}

TEST(FaceVarying, ObjTextureVerticesBecomeTheMeshUvs) {
  const ControlMesh mesh = readObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0.5\nvt 1 0\nvt 1 1 0\nvt 0 1\n"
                                   "f 1/1 2/-3/1 3/3 4/-1\n",
                                   "quad.obj");
  ASSERT_TRUE(mesh.hasUvs());
  EXPECT_EQ(mesh.uvs, (std::vector<float>{0.5f, 0, 1, 0, 1, 1, 0, 1}));
  EXPECT_EQ(mesh.uvIndices, (std::vector<int>{0, 1, 2, 3}));
  // vt lines that no face uses carry nothing.
  EXPECT_FALSE(readObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2 3\n", "tri.obj").hasUvs());
}

TEST(FaceVarying, ObjUvsOnSomeFacesOnlyOrOutOfRangeAreRefusedWithTheirLine) {
  auto message = [](const std::string& obj) {
    try {
      readObj(obj, "m.obj");
    } catch (const TesseraError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  const std::string v = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\n";
  EXPECT_EQ(message(v + "f 1/1 2/1 3/1\nf 1 3 4\n"),
            "m.obj:7: face 1 has no texture coordinates, but the face on line 6 has: give every face UVs or none");
  EXPECT_EQ(message(v + "f 1/1 2 3/1\n"), "m.obj:6: face gives texture coordinates for some corners but not all");
  EXPECT_EQ(message(v + "f 1/1 2/2 3/1\n"), "m.obj:6: texture vertex index 2 is out of range: the file has 1 texture vertices");
  EXPECT_EQ(message(v + "f 1/-2 2/1 3/1\n"),
            "m.obj:6: relative texture vertex index -2 reaches before the first texture vertex (1 read so far)");
}

TEST(FaceVarying, StoredEncodingKeepsUvsAndRuleAndLeavesMeshesWithoutThemAsTheyWere) {
  ControlMesh mesh = texturedPrism();
  mesh.rules.uvInterpolation = UvInterpolation::kCornersPlus1;
  const ControlMesh back = decodeCanonicalMesh(encodeCanonicalMesh(mesh));
  EXPECT_EQ(back.uvs, mesh.uvs);
  EXPECT_EQ(back.uvIndices, mesh.uvIndices);
  EXPECT_EQ(back.rules, mesh.rules);
  ControlMesh plain = mesh;
  plain.uvs.clear(), plain.uvIndices.clear(), plain.rules.uvInterpolation = UvInterpolation::kAll;
  const std::string encoded = encodeCanonicalMesh(plain);
  EXPECT_EQ(encoded.size(), encodeCanonicalMesh(mesh).size() - 4 - 16 - 4 * mesh.uvs.size() - 4 * mesh.uvIndices.size());  // tag, counts, values
  // A mesh without UVs under the default rule has the rules code it had before UVs existed.
  EXPECT_EQ(rulesCode(plain.rules), 1u);
  for (UvInterpolation rule : kEveryRule) {
    SubdivisionRules rules;
    rules.uvInterpolation = rule;
    EXPECT_EQ(rulesFromCode(rulesCode(rules)), rules);
    EXPECT_EQ(parseUvInterpolation(uvInterpolationName(rule)), rule);
  }
}

TEST(FaceVarying, UvsAreValidatedWithTheCornerThatIsWrong) {
  ControlMesh mesh = texturedPrism();
  mesh.uvIndices[7] = 99;
  try {
    validateControlMesh(mesh);
    FAIL() << "accepted";
  } catch (const TesseraError& error) {
    EXPECT_STREQ(error.what(), "face 1 corner 3 uses UV 99, but the mesh has 22 UVs");
  }
  mesh = texturedPrism();
  mesh.uvs[3] = NAN;
  EXPECT_THROW(validateControlMesh(mesh), TesseraError);
  mesh = texturedPrism();
  mesh.uvIndices.pop_back();
  EXPECT_THROW(validateControlMesh(mesh), TesseraError);
}

// FVAR_LINEAR_ALL against the hand-derived bilinear UVs, at every corner of every output triangle.
TEST(FaceVarying, LinearUvsAreTheControlPolygonsAtEveryCorner) {
  for (auto [name, mesh] : texturedMeshes()) {
    mesh.rules.uvInterpolation = UvInterpolation::kAll;
    const PatchSet patches = buildPatchSet(mesh);
    for (double eps : {1e-2, 1e-3}) {
      const TriangleMesh m = tessellateAt(mesh, patches, eps).mesh;
      ASSERT_EQ(m.uvs.size(), 2 * m.positions.size()) << name;
      const double worst = worstCornerError(m, [&](int f, int s, double u, double v, std::array<double, 2>& uv) {
        uv = linearUv(mesh, f, s, u, v);
        return true;
      });
      EXPECT_LT(worst, 2e-6) << name << " at " << eps;
    }
  }
}

// Every rule against OpenSubdiv's own face-varying evaluation (Bfr at approximation level 10).
TEST(FaceVarying, SmoothedUvsMatchOpenSubdivForEveryRule) {
  for (auto [name, mesh] : texturedMeshes()) {
    for (UvInterpolation rule : kEveryRule) {
      mesh.rules.uvInterpolation = rule;
      const PatchSet patches = buildPatchSet(mesh);
      testing::BfrReference bfr(mesh);
      const TriangleMesh m = tessellateAt(mesh, patches, 1e-3).mesh;
      const double worst = worstCornerError(m, [&](int f, int s, double u, double v, std::array<double, 2>& uv) {
        return bfr.evaluateUv(f, s, u, v, uv.data());
      });
      EXPECT_LT(worst, 1e-5) << name << " under " << uvInterpolationName(rule);
    }
  }
}

// UVs add seam copies, never move geometry: the triangles' corner positions are bit for bit those
// of the same mesh without UVs, each copy repeats its vertex's position, and the copies close up
// (no edge of the surface is open once copies are taken as their vertex, but the input's own).
TEST(FaceVarying, SeamsSplitVerticesWithoutMovingThem) {
  for (const char* name : {"catmark_torus_creases0", "catmark_cube_creases2", "catmark_fvar_bound1"}) {
    const ControlMesh mesh = shape(name);
    ASSERT_TRUE(mesh.hasUvs()) << name;
    ControlMesh plain = mesh;
    plain.uvs.clear(), plain.uvIndices.clear();
    const TriangleMesh a = tessellateAt(mesh, buildPatchSet(mesh), 1e-3).mesh;
    const TriangleMesh b = tessellateAt(plain, buildPatchSet(plain), 1e-3).mesh;
    ASSERT_EQ(a.indices.size(), b.indices.size()) << name;
    EXPECT_GT(a.positions.size(), b.positions.size()) << name << ": no seam copies";
    for (size_t c = 0; c < a.indices.size(); ++c) {
      const Vec3 &p = a.positions[a.indices[c]], &q = b.positions[b.indices[c]];
      ASSERT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z) << name << " corner " << c;
      ASSERT_EQ(a.vertexPoint[a.indices[c]], b.vertexPoint[b.indices[c]]) << name << " corner " << c;
    }
    for (size_t v = 0; v < a.positions.size(); ++v) {
      const Vec3 &p = a.positions[v], &q = a.positions[a.vertexPoint[v]];
      ASSERT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z) << name << " vertex " << v;
    }
  }
}

// Where the UVs are continuous (one UV per control vertex), across n-gons' edges and corners too,
// no vertex is copied.
TEST(FaceVarying, ContinuousUvsCopyNoVertex) {
  for (ControlMesh mesh : {texturedPrism(), shape("catmark_nonquads"), shape("catmark_fvar_bound0")}) {
    mesh.uvs.clear();
    for (const Vec3& p : mesh.positions) mesh.uvs.insert(mesh.uvs.end(), {p.x + 0.25f * p.y, p.z - 0.5f * p.y});
    mesh.uvIndices = mesh.faceVertices;
    ControlMesh plain = mesh;
    plain.uvs.clear(), plain.uvIndices.clear();
    const TriangleMesh a = tessellateAt(mesh, buildPatchSet(mesh), 1e-3).mesh;
    const TriangleMesh b = tessellateAt(plain, buildPatchSet(plain), 1e-3).mesh;
    EXPECT_EQ(a.positions.size(), b.positions.size());
    EXPECT_EQ(a.indices, b.indices);
  }
}

// TEXCOORD_0 in every encoding: what a viewer reads back is the UV of each corner, and
// glTF-Validator finds nothing to report.
TEST(FaceVarying, GlbCarriesTexcoordsInEveryEncoding) {
  const ControlMesh mesh = texturedPrism();
  const TriangleMesh m = tessellateAt(mesh, buildPatchSet(mesh), 1e-3).mesh;
  for (GlbEncoding encoding : {GlbEncoding::kFloat, GlbEncoding::kQuantized, GlbEncoding::kMeshopt}) {
    GlbOptions options;
    options.encoding = encoding;
    options.description.sourceName = "prism";
    const std::vector<uint8_t> glb = writeGlb(m, options);
    const TriangleMesh back = testing::readGlb(glb);
    ASSERT_EQ(back.indices.size(), m.indices.size());
    ASSERT_EQ(back.uvs.size(), 2 * back.positions.size());
    // meshopt reorders triangles: compare the multiset of corner UVs.
    std::multiset<std::pair<float, float>> written, read;
    for (size_t c = 0; c < m.indices.size(); ++c) {
      written.insert({m.uvs[2 * m.indices[c]], m.uvs[2 * m.indices[c] + 1]});
      read.insert({back.uvs[2 * back.indices[c]], back.uvs[2 * back.indices[c] + 1]});
    }
    EXPECT_EQ(written, read) << glbEncodingName(encoding);
    const testing::ValidatorReport report = testing::validateGlb(glb, std::string("uvs-") + glbEncodingName(encoding));
    if (!report.ran) GTEST_SKIP() << report.report;
    EXPECT_TRUE(report.clean()) << report.report;
  }
}

}  // namespace
}  // namespace tessera
