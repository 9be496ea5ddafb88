// Device choice: the ranking policy on made-up device lists, and the real selection on this
// machine (lavapipe in CI).
#include <gtest/gtest.h>

#include <vector>

#include "gpu/vulkan/device_ranking.h"
#include "gpu/vulkan/vulkan_error.h"
#include "render_test_support.h"

namespace tessera::gpu::testing {
namespace {

DeviceCandidate candidate(const char* name, uint32_t vendor, DeviceKind kind, bool usable = true) {
  return {name, vendor, kind, usable, usable ? "" : "Vulkan 1.3 required"};
}

const std::vector<DeviceCandidate> kMixed = {
    candidate("llvmpipe (LLVM 15.0.6, 256 bits)", 0x10005, DeviceKind::kCpu),
    candidate("AMD Radeon RX 7900", 0x1002, DeviceKind::kDiscrete),
    candidate("Intel(R) UHD Graphics", 0x8086, DeviceKind::kIntegrated),
    candidate("NVIDIA H100 80GB HBM3", kVendorNvidia, DeviceKind::kDiscrete),
};

TEST(DeviceSelection, AutomaticPrefersNvidiaThenDiscreteThenIntegratedThenCpu) {
  EXPECT_EQ(chooseDevice(kMixed, {}), 3u);
  std::vector<DeviceCandidate> noNvidia(kMixed.begin(), kMixed.begin() + 3);
  EXPECT_EQ(chooseDevice(noNvidia, {}), 1u);
  std::vector<DeviceCandidate> cpuAndIntegrated = {kMixed[0], kMixed[2]};
  EXPECT_EQ(chooseDevice(cpuAndIntegrated, {}), 1u);
  std::vector<DeviceCandidate> cpuOnly = {kMixed[0]};
  EXPECT_EQ(chooseDevice(cpuOnly, {}), 0u);
}

TEST(DeviceSelection, SkipsUnusableDevices) {
  std::vector<DeviceCandidate> list = kMixed;
  list[3].usable = false;
  list[1].usable = false;
  EXPECT_EQ(chooseDevice(list, {}), 2u);
}

TEST(DeviceSelection, OverridesByNameSubstringOrIndex) {
  DeviceSelection byName;
  byName.nameContains = "LLVMPIPE";  // case-insensitive
  EXPECT_EQ(chooseDevice(kMixed, byName), 0u);
  DeviceSelection byIndex;
  byIndex.index = 2;
  EXPECT_EQ(chooseDevice(kMixed, byIndex), 2u);
}

TEST(DeviceSelection, OverrideMatchingNothingListsTheDevices) {
  DeviceSelection selection;
  selection.nameContains = "voodoo";
  try {
    chooseDevice(kMixed, selection);
    FAIL() << "expected RenderUnsupportedError";
  } catch (const RenderUnsupportedError& e) {
    std::string message = e.what();
    EXPECT_NE(message.find("voodoo"), std::string::npos) << message;
    EXPECT_NE(message.find("NVIDIA H100"), std::string::npos) << message;
  }
  DeviceSelection badIndex;
  badIndex.index = 9;
  EXPECT_THROW(chooseDevice(kMixed, badIndex), RenderUnsupportedError);
  EXPECT_THROW(chooseDevice({}, DeviceSelection{}), RenderUnsupportedError);
}

TEST(DeviceSelection, FindsLavapipeByName) {
  DeviceSelection selection;
  selection.nameContains = "llvmpipe";
  selection.validation = true;
  try {
    Renderer renderer = Renderer::create(selection);
    DeviceInfo info = renderer.info();
    EXPECT_NE(info.name.find("llvmpipe"), std::string::npos);
    EXPECT_EQ(info.kind, DeviceKind::kCpu);
    EXPECT_GE(info.apiVersion, VK_API_VERSION_1_3);
    EXPECT_TRUE(info.timestamps);  // lavapipe implements timestamp queries
    EXPECT_EQ(renderer.hasMeshShaders(), info.meshShaders);
  } catch (const RenderUnsupportedError& e) {
    GTEST_SKIP() << "lavapipe is not installed: " << e.what();
  }
}

TEST(DeviceSelection, AutomaticChoiceIsAtLeastAsGoodAsTheCpu) {
  Renderer renderer = Renderer::create(DeviceSelection{});
  DeviceInfo info = renderer.info();
  DeviceCandidate chosen = candidate(info.name.c_str(), info.vendorId, info.kind);
  EXPECT_LE(deviceRank(chosen), deviceRank(candidate("cpu", 0, DeviceKind::kCpu)));
  EXPECT_FALSE(info.name.empty());
}

TEST(DeviceSelection, MeshPathOnADeviceWithoutItIsAClearError) {
  Renderer renderer = makeTestRenderer();
  if (renderer.hasMeshShaders()) GTEST_SKIP() << "this device has VK_EXT_mesh_shader";
  RenderOptions options;
  options.path = GeometryPath::kMeshShader;
  try {
    renderer.render({}, Camera{}, options);
    FAIL() << "expected RenderUnsupportedError";
  } catch (const RenderUnsupportedError& e) {
    EXPECT_NE(std::string(e.what()).find("VK_EXT_mesh_shader"), std::string::npos) << e.what();
  }
  options.path = GeometryPath::kAuto;
  Camera small;
  small.width = small.height = 8;
  EXPECT_EQ(renderer.render({}, small, options).pathUsed, GeometryPath::kCompute);
}

TEST(DeviceSelection, VkResultNamesAreReadable) {
  EXPECT_EQ(vkResultName(VK_ERROR_DEVICE_LOST), "VK_ERROR_DEVICE_LOST");
  EXPECT_EQ(vkResultName(static_cast<VkResult>(-12345)), "VkResult(-12345)");
  VulkanError error("vkAllocateMemory", VK_ERROR_OUT_OF_DEVICE_MEMORY);
  EXPECT_STREQ(error.what(), "vkAllocateMemory failed: VK_ERROR_OUT_OF_DEVICE_MEMORY");
}

}  // namespace
}  // namespace tessera::gpu::testing
