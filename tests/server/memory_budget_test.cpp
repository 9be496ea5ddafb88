// The server's memory budget (--memory-budget): a job whose estimated memory could never fit is
// refused before the work with RESOURCE_EXHAUSTED naming the estimate and the budget, at upload
// when preprocessing alone is too much; the server stays within its budget and serves the next
// request. The frame case is in tests/render_server/frame_memory_test.cpp.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "tests/server/process_memory.h"
#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

struct Tessellated {
  grpc::Status status;
  int64_t glbBytes = 0;
  double seconds = 0;
};

Tessellated tessellate(v1::TessellationService::Stub& stub, const v1::TessellateRequest& request) {
  grpc::ClientContext context;
  prepare(context, {}, 120);
  const auto start = std::chrono::steady_clock::now();
  auto reader = stub.Tessellate(&context, request);
  v1::TessellateResponse message;
  Tessellated out;
  while (reader->Read(&message)) {
    if (message.has_glb_chunk()) out.glbBytes += int64_t(message.glb_chunk().data().size());
  }
  out.status = reader->Finish();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// 1 GiB less 64 MiB + 64 MiB of caches and 128 MiB for the server: 768 MiB for jobs. armorguy's
// refinement alone is estimated at ~1.6 GiB (core/pipeline/memory_estimates.h).
TEST(MemoryBudget, AMeshWhosePreprocessingCannotFitIsRefusedAtUpload) {
  TempDir dir;
  auto server = ServerProcess::start(
      dir.path(), {"--memory-budget", "1GiB", "--cache-bytes", "64MiB", "--patch-cache-bytes", "64MiB"});
  ASSERT_TRUE(server);
  auto meshes = v1::MeshService::NewStub(server->channel());
  const UploadResult refused = uploadModel(*meshes, "armorguy");
  EXPECT_EQ(refused.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  const std::string& message = refused.status.error_message();
  EXPECT_TRUE(contains(message, "preprocessing the mesh needs about")) << message;
  EXPECT_TRUE(contains(message, "memory budget for jobs of 768 MiB")) << message;
  EXPECT_TRUE(uploadModel(*meshes, "bigguy").status.ok());
}

// armorguy at uniform level 40 is ~28 million triangles, inside the default --max-triangles but
// ~11 GB of output: refused once the plan has counted them, before any is made. The server's
// peak stays within its 3 GiB budget and it tessellates the same mesh at 1e-3 afterwards.
TEST(MemoryBudget, AnOutputThatCannotFitIsRefusedAndTheServerStaysWithinItsBudget) {
  TempDir dir;
  auto server = ServerProcess::start(
      dir.path(), {"--memory-budget", "3GiB", "--cache-bytes", "256MiB", "--patch-cache-bytes", "256MiB"});
  ASSERT_TRUE(server);
  auto meshes = v1::MeshService::NewStub(server->channel());
  ASSERT_TRUE(uploadModel(*meshes, "armorguy").status.ok());
  auto tessellation = v1::TessellationService::NewStub(server->channel());

  v1::TessellateRequest huge;
  huge.set_name("meshes/armorguy");
  huge.set_uniform_level(40);
  const Tessellated refused = tessellate(*tessellation, huge);
  EXPECT_EQ(refused.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  const std::string& message = refused.status.error_message();
  EXPECT_TRUE(contains(message, "the output (")) << message;
  EXPECT_TRUE(contains(message, "triangles) needs about")) << message;
  EXPECT_TRUE(contains(message, "memory budget for jobs of 2.4 GiB")) << message;
  EXPECT_EQ(refused.glbBytes, 0);

  v1::TessellateRequest normal;
  normal.set_name("meshes/armorguy");
  normal.set_relative(1e-3);
  const Tessellated served = tessellate(*tessellation, normal);
  EXPECT_TRUE(served.status.ok()) << served.status.error_message();
  EXPECT_GT(served.glbBytes, 1 << 20);

  const int64_t peak = processMemoryBytes(server->pid(), "VmHWM");
  const std::string metrics = httpGet(server->metricsAddress(), "/metrics");
  std::printf("peak %.0f MiB of a 3072 MiB budget; refused in %.2f s\n", peak / 1048576.0, refused.seconds);
  EXPECT_LE(peak, int64_t(3) << 30);
  EXPECT_EQ(seriesValue(metrics, "tessera_memory_reserved_bytes"), 0.0);
  EXPECT_EQ(seriesValue(metrics, "tessera_memory_budget_bytes"), double(int64_t(3072 - 512 - 128) << 20));
}

TEST(MemoryBudget, ABudgetThatLeavesNothingForJobsIsAConfigurationError) {
  TempDir dir;
  const auto [code, output] = failedStart(dir.path(), "--memory-budget 600MiB");
  EXPECT_NE(code, 0);
  EXPECT_TRUE(contains(output, "--memory-budget 600 MiB leaves 0 bytes for jobs")) << output;
}

}  // namespace
}  // namespace tessera::test
