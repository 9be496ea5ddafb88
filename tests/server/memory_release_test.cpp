// Memory a job freed goes back to the operating system when its call ends: after a large
// tessellation the server's resident memory is what it was before plus what its caches now hold
// (the patch set and the decoded mesh), not the job's peak.
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/server/process_memory.h"
#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

// armorguy at 1e-4: 1.4 million triangles, a peak some 600 MB above the resting server; without
// giving memory back the server kept ~160 MB of it past its caches.
TEST(MemoryRelease, ALargeTessellationLeavesOnlyWhatTheCachesHold) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {});
  ASSERT_TRUE(server);
  auto meshes = v1::MeshService::NewStub(server->channel());
  ASSERT_TRUE(uploadModel(*meshes, "armorguy").status.ok());
  const int64_t before = processMemoryBytes(server->pid(), "VmRSS");
  const std::string metricsBefore = httpGet(server->metricsAddress(), "/metrics");

  auto tessellation = v1::TessellationService::NewStub(server->channel());
  grpc::ClientContext context;
  prepare(context, {}, 120);
  v1::TessellateRequest request;
  request.set_name("meshes/armorguy");
  request.set_relative(1e-4);
  auto reader = tessellation->Tessellate(&context, request);
  v1::TessellateResponse message;
  int64_t glbBytes = 0;
  while (reader->Read(&message)) {
    if (message.has_glb_chunk()) glbBytes += int64_t(message.glb_chunk().data().size());
  }
  ASSERT_TRUE(reader->Finish().ok());
  ASSERT_GT(glbBytes, 20 << 20);

  const int64_t after = processMemoryBytes(server->pid(), "VmRSS");
  const int64_t peak = processMemoryBytes(server->pid(), "VmHWM");
  const std::string metrics = httpGet(server->metricsAddress(), "/metrics");
  const double cached = seriesValue(metrics, "tessera_patch_cache_bytes") + seriesValue(metrics, "tessera_cache_bytes") -
                        seriesValue(metricsBefore, "tessera_patch_cache_bytes") - seriesValue(metricsBefore, "tessera_cache_bytes");
  std::printf("VmRSS %.0f MiB before, %.0f MiB after (peak %.0f MiB); caches grew by %.0f MiB\n", before / 1048576.0,
              after / 1048576.0, peak / 1048576.0, cached / 1048576.0);
  EXPECT_GT(peak - before, int64_t(300) << 20);  // the job was large
  EXPECT_LT(double(after - before) - cached, double(64 << 20));
}

}  // namespace
}  // namespace tessera::test
