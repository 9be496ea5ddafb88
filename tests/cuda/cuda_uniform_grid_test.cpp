// The uniform grid on a CUDA device against the CPU's evaluateUniformGrid, bit for bit (both run
// core/math/grid_sample.h without multiply-add contraction). Needs a CUDA device; without one the
// tests are skipped with CUDA's reason.
#include "core/pipeline/preprocessing.h"
#include "gpu/cuda/cuda_uniform_grid.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "core/base/error.h"
#include "core/mesh/obj_reader.h"
#include "gpu/cuda/device_info.h"
#include "reference/models.h"
#include "tests/cuda/grid_cases.h"

namespace tessera::cuda {
namespace {

const CudaDeviceInfo& device() {
  static const CudaDeviceInfo info = queryCudaDevice();
  return info;
}

size_t differingSamples(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  size_t differing = 0;
  for (size_t i = 0; i < a.size(); ++i) differing += std::memcmp(&a[i], &b[i], sizeof(Vec3)) != 0;
  return differing;
}

TEST(CudaUniformGrid, EqualsTheCpuGridBitForBit) {
  if (!device().available) GTEST_SKIP() << "no CUDA device: " << device().reason;
  testing::forEachGridCase(
      GridKernel::kAvx2, [](const std::string& name, int p, const PatchSet& patches,
                            const UniformGrid& grid, const std::vector<Vec3>& expected) {
        CudaUniformGrid gpu(patches, grid);
        gpu.launch();
        const std::vector<Vec3> first = gpu.download();
        EXPECT_EQ(differingSamples(first, expected), 0u) << name << " p=" << p;
        gpu.launch();  // a second launch over the same buffers writes the same samples
        EXPECT_EQ(differingSamples(gpu.download(), first), 0u) << name << " p=" << p;
      });
}

TEST(CudaUniformGrid, WithoutADeviceTheErrorNamesCuda) {
  if (device().available) GTEST_SKIP() << "a CUDA device is present: " << device().summary();
  const PatchSet set = buildPatchSet(readObjFile(tessera::testing::modelsDir() + "/bigguy.obj"));
  UniformGrid grid;
  planUniformGrid(set, 4, grid);
  try {
    CudaUniformGrid gpu(set, grid);
    FAIL() << "constructed without a device";
  } catch (const TesseraError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("no CUDA device: ", 0), 0u) << error.what();
  }
}

}  // namespace
}  // namespace tessera::cuda
