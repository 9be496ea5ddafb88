// Frames under the server's memory budget: a frame whose pixels alone could never fit is refused
// at once with RESOURCE_EXHAUSTED naming its size and the budget (8192 x 8192 RAW_RGBA took 4.5 GB
// at its peak before); one that fits is drawn, and the server's peak stays within the budget.
// And a large frame's memory is given back when it is done, not held until the next frame.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <map>

#include "tests/render_server/render_test_support.h"
#include "tests/server/process_memory.h"

namespace tessera::test {
namespace {

// 2 GiB less 64 + 128 MiB of caches and 128 MiB for the server: 1728 MiB for jobs.
TEST(FrameMemory, AFrameOverTheBudgetIsRefusedAtOnceAndOneWithinItIsDrawnWithinIt) {
  TempDir dir;
  std::map<std::string, std::string> env;
  if (const char* device = std::getenv("TESSERA_VK_DEVICE")) env["TESSERA_VK_DEVICE"] = device;
  auto server = ServerProcess::start(
      dir.path(), {"--memory-budget", "2GiB", "--cache-bytes", "64MiB", "--patch-cache-bytes", "128MiB"}, env);
  ASSERT_TRUE(server);
  auto meshes = v1::MeshService::NewStub(server->channel());
  ASSERT_TRUE(uploadModel(*meshes, "bigguy").status.ok());
  auto stub = v1::RenderService::NewStub(server->channel());

  const auto start = std::chrono::steady_clock::now();
  RenderCall huge = render(*stub, renderRequest({framedCamera({0, 0, 1}, 8192, 8192)}, v1::IMAGE_FORMAT_RAW_RGBA));
  const double refusedSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(huge.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  const std::string& message = huge.status.error_message();
  EXPECT_NE(message.find("a 8192 x 8192 frame needs about"), std::string::npos) << message;
  EXPECT_NE(message.find("memory budget for jobs of 1.7 GiB"), std::string::npos) << message;
  EXPECT_TRUE(huge.frames.empty());
  EXPECT_LT(refusedSeconds, 5.0) << "refused before any work";

  const int64_t before = processMemoryBytes(server->pid(), "VmHWM");
  RenderCall large = render(*stub, renderRequest({framedCamera({0, 0, 1}, 4096, 4096)}, v1::IMAGE_FORMAT_RAW_RGBA));
  ASSERT_TRUE(large.status.ok()) << large.status.error_message();
  ASSERT_EQ(large.frames.size(), 1u);
  EXPECT_EQ(large.frames[0].bytes.size(), size_t(4096) * 4096 * 4);
  const int64_t peak = processMemoryBytes(server->pid(), "VmHWM");
  std::printf("4096 x 4096 frame: peak %.0f MiB (%.1f bytes a pixel over the peak before it) of a 2048 MiB budget\n",
              peak / 1048576.0, double(peak - before) / (4096.0 * 4096.0));
  EXPECT_LE(peak, int64_t(2) << 30);

  RenderCall small = render(*stub, renderRequest({framedCamera({0, 0, 1}, 64, 64)}, v1::IMAGE_FORMAT_PNG));
  EXPECT_TRUE(small.status.ok()) << small.status.error_message();
}

// The renderer kept a frame's render targets for the next frame of the same size: after one
// 4096 x 4096 frame the server held ~750 MB more until its next frame (an 8192 x 8192 one, ~2.9 GB;
// issue 47). Now what a frame leaves is what the caches hold, and the small targets it may keep.
TEST(FrameMemory, ALargeFramesMemoryIsGivenBackWhenItIsDone) {
  TempDir dir;
  std::map<std::string, std::string> env;
  if (const char* device = std::getenv("TESSERA_VK_DEVICE")) env["TESSERA_VK_DEVICE"] = device;
  auto server = ServerProcess::start(dir.path(), {}, env);
  ASSERT_TRUE(server);
  auto meshes = v1::MeshService::NewStub(server->channel());
  ASSERT_TRUE(uploadModel(*meshes, "bigguy").status.ok());
  auto stub = v1::RenderService::NewStub(server->channel());
  // A small frame first: the device, its pipelines and bigguy's patch set are the resting server's.
  ASSERT_TRUE(render(*stub, renderRequest({framedCamera({0, 0, 1}, 64, 64)})).status.ok());
  const int64_t before = processMemoryBytes(server->pid(), "VmRSS");
  const std::string metricsBefore = httpGet(server->metricsAddress(), "/metrics");

  RenderCall large = render(*stub, renderRequest({framedCamera({0, 0, 1}, 4096, 4096)}, v1::IMAGE_FORMAT_RAW_RGBA));
  ASSERT_TRUE(large.status.ok()) << large.status.error_message();
  ASSERT_EQ(large.frames.size(), 1u);

  const int64_t after = processMemoryBytes(server->pid(), "VmRSS");
  const int64_t peak = processMemoryBytes(server->pid(), "VmHWM");
  const std::string metrics = httpGet(server->metricsAddress(), "/metrics");
  const double cached = seriesValue(metrics, "tessera_patch_cache_bytes") + seriesValue(metrics, "tessera_cache_bytes") -
                        seriesValue(metricsBefore, "tessera_patch_cache_bytes") - seriesValue(metricsBefore, "tessera_cache_bytes");
  std::printf("4096 x 4096 RAW frame: VmRSS %.0f MiB before, %.0f MiB after (peak %.0f MiB); caches grew by %.0f MiB\n",
              before / 1048576.0, after / 1048576.0, peak / 1048576.0, cached / 1048576.0);
  EXPECT_GT(peak - before, int64_t(600) << 20);  // the frame was large
  // Before the fix: ~830 MiB. What remains is allocator and driver slack (10-55 MiB measured).
  EXPECT_LT(double(after - before) - cached, double(128 << 20));
}

}  // namespace
}  // namespace tessera::test
