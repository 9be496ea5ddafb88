// Meshes far from the origin and at any scale keep their bound: the OBJ reader takes positions
// relative to the box's centre (in double) when float would round the detail away, tessellation
// and pixel accuracy work relative to it, and the GLB's node carries it as its translation.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/output/glb_writer.h"
#include "core/mesh/mesh_codec.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
#include "tests/support/glb_reader.h"
#include "reference/limit_distance.h"
#include "reference/limit_surface.h"
#include "reference/models.h"

namespace tessera {
namespace {

const Vec3d kFar(1e6, -2e6, 5e5);

// The model's OBJ with every position p written as scale·p + offset, computed in double and
// printed with every digit, the tags kept.
std::string transformedObj(const std::string& path, double scale, const Vec3d& offset) {
  const ControlMesh mesh = readObjFile(path);
  std::string obj;
  char line[160];
  for (const Vec3& p : mesh.positions) {
    const Vec3d q = Vec3d(p) * scale + offset;
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", q.x, q.y, q.z);
    obj += line;
  }
  size_t corner = 0;
  for (int size : mesh.faceSizes) {
    obj += "f";
    for (int k = 0; k < size; ++k) {
      obj += ' ';  // appended: `" " + std::string` trips GCC 12's -Wrestrict (105651)
      obj += std::to_string(mesh.faceVertices[corner++] + 1);
    }
    obj += "\n";
  }
  for (const CreaseEdge& c : mesh.creases) {
    std::snprintf(line, sizeof line, "t crease 2/1/0 %d %d %.9g\n", c.v0, c.v1, c.sharpness);
    obj += line;
  }
  for (const CornerVertex& c : mesh.corners) {
    std::snprintf(line, sizeof line, "t corner 1/1/0 %d %.9g\n", c.vertex, c.sharpness);
    obj += line;
  }
  return obj;
}

TessellationResult tessellateAt(const ControlMesh& mesh, double relative, std::optional<Camera> camera = {}) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(relative);
  options.recordParameters = true;  // the measure's parametric seeds (reference/limit_distance.h)
  if (camera) options.camera = camera, options.accuracy = Accuracy::pixel(0.5);
  return tessellate(buildPatchSet(mesh), mesh, options);
}

struct Case {
  const char* model;
  double scale;
};

// The far mesh's output, moved back by the offset in double, measured against the limit surface
// of the same mesh near the origin (float positions that hold it exactly enough): within ε.
TEST(FarFromOrigin, TranslatedAndScaledMeshesKeepTheirBound) {
  for (const Case c : {Case{"bigguy.obj", 1e-3}, Case{"bigguy.obj", 1e3}, Case{"opensubdiv-shapes/catmark_cube_creases2.obj", 1.0}}) {
    SCOPED_TRACE(std::string(c.model) + " scaled by " + std::to_string(c.scale));
    const std::string path = testing::modelsDir() + "/" + c.model;
    const ControlMesh far = readObj(transformedObj(path, c.scale, kFar), "far.obj");
    const ControlMesh near = readObj(transformedObj(path, c.scale, Vec3d(0, 0, 0)), "near.obj");
    EXPECT_NE(far.origin.x, 0.0);
    EXPECT_EQ(near.origin.x, 0.0);
    const testing::LimitSurface surface(near);
    for (double eps : {1e-3, 1e-4}) {
      const TriangleMesh m = tessellateAt(far, eps).mesh;
      EXPECT_EQ(m.origin.x, far.origin.x);
      std::vector<Vec3> back(m.positions.size());
      for (size_t v = 0; v < back.size(); ++v) back[v] = Vec3(Vec3d(m.positions[v]) + m.origin - kFar);
      testing::TriangleMeshView view = testing::viewOf(m);
      view.positions = back;
      const testing::LimitDistanceReport report = testing::measureLimitDistance(surface, view);
      EXPECT_LE(report.twoSidedRelative(), eps * 1.01) << "at " << eps;
      EXPECT_GT(report.twoSidedRelative(), eps * 0.1) << "at " << eps << ": suspiciously coarse measure";
    }
  }
}

// The GLB's node translation is the origin, in full double precision, in every encoding (the
// quantized grid's centre added to it).
TEST(FarFromOrigin, GlbNodeCarriesTheOrigin) {
  const ControlMesh far = readObj(transformedObj(testing::modelsDir() + "/bigguy.obj", 1e-3, kFar), "far.obj");
  const TriangleMesh m = tessellateAt(far, 1e-3).mesh;
  const std::vector<uint8_t> glb = writeGlb(m, {});
  uint32_t length = 0;
  std::memcpy(&length, glb.data() + 12, 4);
  const nlohmann::json json = nlohmann::json::parse(glb.begin() + 20, glb.begin() + 20 + length);
  const nlohmann::json& t = json["nodes"][0]["translation"];
  EXPECT_EQ(t[0].get<double>(), far.origin.x);
  EXPECT_EQ(t[1].get<double>(), far.origin.y);
  EXPECT_EQ(t[2].get<double>(), far.origin.z);
  // What a viewer sees (float positions through the translation) lies where the model is.
  const TriangleMesh seen = testing::readGlb(glb);
  EXPECT_NEAR(seen.positions[0].x, m.positions[0].x + far.origin.x, 0.2);
}

TEST(FarFromOrigin, StoredEncodingKeepsTheOriginAndNearMeshesHaveNone) {
  const ControlMesh far = readObj(transformedObj(testing::modelsDir() + "/bigguy.obj", 1.0, kFar), "far.obj");
  const ControlMesh back = decodeCanonicalMesh(encodeCanonicalMesh(far));
  EXPECT_EQ(back.origin.x, far.origin.x);
  EXPECT_EQ(back.origin.y, far.origin.y);
  EXPECT_EQ(back.origin.z, far.origin.z);
  EXPECT_EQ(back.positions.size(), far.positions.size());
  // The paper's models sit near the origin: read as before, no origin.
  for (const std::string& path : testing::benchmarkCharacters()) {
    const ControlMesh mesh = readObjFile(path);
    EXPECT_EQ(mesh.origin.x, 0.0) << path;
    EXPECT_EQ(mesh.origin.y, 0.0) << path;
    EXPECT_EQ(mesh.origin.z, 0.0) << path;
  }
}

// A camera is given in model units: the same view of the far mesh as of the near one makes the
// same triangles, give or take the positions' last bits.
TEST(FarFromOrigin, PixelAccuracyUsesTheCameraInModelUnits) {
  const std::string path = testing::modelsDir() + "/bigguy.obj";
  const ControlMesh far = readObj(transformedObj(path, 1.0, kFar), "far.obj");
  const ControlMesh near = readObj(transformedObj(path, 1.0, Vec3d(0, 0, 0)), "near.obj");
  Camera camera;
  camera.eye = Vec3d(0, 2, 14), camera.target = Vec3d(0, 2, 0), camera.width = 1280, camera.height = 720;
  Camera farCamera = camera;
  farCamera.eye = camera.eye + kFar, farCamera.target = camera.target + kFar;
  const int64_t nearTriangles = tessellateAt(near, 1e-3, camera).summary.triangles;
  const int64_t farTriangles = tessellateAt(far, 1e-3, farCamera).summary.triangles;
  EXPECT_NEAR(double(farTriangles), double(nearTriangles), 0.02 * double(nearTriangles));
}

}  // namespace
}  // namespace tessera
