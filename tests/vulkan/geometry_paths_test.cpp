// The mesh-shader and compute paths share their GLSL, so they must draw the same image.
// Runs only on devices with VK_EXT_mesh_shader (not lavapipe in Mesa 22.3).
#include <gtest/gtest.h>

#include "render_test_support.h"

namespace tessera::gpu::testing {
namespace {

TEST(GeometryPaths, MeshAndComputePathsAgree) {
  Renderer renderer = makeTestRenderer();
  if (!renderer.hasMeshShaders()) GTEST_SKIP() << "device has no VK_EXT_mesh_shader";
  std::vector<RenderPatch> patches =
      makeSphere(Vec3d(0.2, 0, 0), 1.0, 3, hashedEdgeLevels(1, 40), 0);
  Camera camera;
  camera.eye = Vec3(0.5f, 1.0f, 3.5f);
  camera.width = camera.height = 256;
  RenderOptions mesh;
  mesh.path = GeometryPath::kMeshShader;
  mesh.crackFilling = false;
  RenderOptions compute = mesh;
  compute.path = GeometryPath::kCompute;
  Frame a = renderer.render(patches, camera, mesh);
  Frame b = renderer.render(patches, camera, compute);
  EXPECT_EQ(a.pathUsed, GeometryPath::kMeshShader);
  EXPECT_EQ(a.trianglesGenerated, b.trianglesGenerated);
  EXPECT_EQ(countDropouts(a), 0u);
  // Interior vertices may differ in the last bit between the two shaders (different FMA
  // contraction), which can flip a pixel on a triangle edge: allow 0.1% of pixels.
  size_t differing = 0;
  for (size_t i = 0; i < a.patchIds.size(); ++i) differing += a.patchIds[i] != b.patchIds[i];
  EXPECT_LE(differing, a.patchIds.size() / 1000);
  expectNoValidationMessages(renderer);
}

}  // namespace
}  // namespace tessera::gpu::testing
