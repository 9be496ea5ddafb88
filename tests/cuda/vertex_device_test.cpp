// The adaptive tessellation with its vertices evaluated on a CUDA device against the CPU engine's,
// bit for bit (both run core/surface/surface_point.h without multiply-add contraction): every supported
// OpenSubdiv shape at 1e-2 and the paper's characters at 1e-3. Needs a CUDA device; without one
// the tests are skipped with CUDA's reason.
#include "core/pipeline/preprocessing.h"
#include "gpu/cuda/cuda_surface.h"

#include <gtest/gtest.h>

#include <string>

#include "core/base/error.h"
#include "gpu/cuda/device_info.h"
#include "tests/cuda/vertex_cases.h"
#include "tests/support/mesh_equality.h"

namespace tessera::cuda {
namespace {

const CudaDeviceInfo& device() {
  static const CudaDeviceInfo info = queryCudaDevice();
  return info;
}

void expectDeviceMatchesCpu(const testing::VertexCase& c) {
  const ControlMesh mesh = testing::readCaseMesh(c.path);
  if (mesh.faceCount() == 0) return;  // refused by the reader (covered by PatchSet's tests)
  const PatchSet patches = buildPatchSet(mesh);
  const CudaSurface surface(patches);
  CudaVertexEvaluation evaluation(surface);
  const TessellationResult cpu = tessellate(patches, mesh, testing::vertexCaseOptions(c.tolerance, nullptr));
  const TessellationResult gpu = tessellate(patches, mesh, testing::vertexCaseOptions(c.tolerance, &evaluation));
  EXPECT_EQ(tessera::testing::meshDifference(gpu.mesh, cpu.mesh), "")
      << tessera::testing::baseName(c.path) << " at " << c.tolerance << " (" << cpu.mesh.positions.size()
      << " vertices)";
}

TEST(CudaVertices, EqualTheCpuEngineOnEveryShape) {
  if (!device().available) GTEST_SKIP() << "no CUDA device: " << device().reason;
  for (const testing::VertexCase& c : testing::vertexCases(false)) expectDeviceMatchesCpu(c);
}

TEST(CudaVertices, EqualTheCpuEngineOnThePapersCharacters) {
  if (!device().available) GTEST_SKIP() << "no CUDA device: " << device().reason;
  for (const testing::VertexCase& c : testing::vertexCases(true)) expectDeviceMatchesCpu(c);
}

TEST(CudaVertices, WithoutADeviceTheErrorNamesCuda) {
  if (device().available) GTEST_SKIP() << "a CUDA device is present: " << device().summary();
  const PatchSet patches = buildPatchSet(readObjFile(tessera::testing::modelsDir() + "/bigguy.obj"));
  try {
    CudaSurface surface(patches);
    FAIL() << "uploaded without a device";
  } catch (const TesseraError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("no CUDA device: ", 0), 0u) << error.what();
  }
}

}  // namespace
}  // namespace tessera::cuda
