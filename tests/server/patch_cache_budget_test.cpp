// The patch-set cache's size and what it drops, as an operator sees them: by default a quarter of
// --memory-budget (the jobs get what the caches and the server leave), and every patch set it
// evicts to make room counted in /metrics, beside the preprocessing the next request for it costs.
#include <gtest/gtest.h>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

constexpr double kMiB = 1 << 20;

std::string metricsOf(const ServerProcess& server) { return httpGet(server.metricsAddress(), "/metrics"); }

// A grid of cells × cells quads.
void uploadAndTessellate(const ServerProcess& server, const std::string& id, int cells, bool upload) {
  auto meshes = v1::MeshService::NewStub(server.channel());
  if (upload) ASSERT_TRUE(uploadMessages(*meshes, arraysUpload(id, gridMesh(cells, 1))).status.ok());
  auto tessellation = v1::TessellationService::NewStub(server.channel());
  v1::TessellateRequest request;
  request.set_name("meshes/" + id);
  request.set_relative(1e-3);
  ASSERT_TRUE(tessellateOverGrpc(*tessellation, request).status.ok());
}

TEST(PatchCacheBudget, TheDefaultIsAQuarterOfTheMemoryBudget) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--memory-budget", "4GiB", "--cache-bytes", "256MiB"});
  ASSERT_TRUE(server);
  // Jobs: 4 GiB less the meshes' 256 MiB, the patch sets' 1 GiB and the server's own 128 MiB.
  EXPECT_EQ(seriesValue(metricsOf(*server), "tessera_memory_budget_bytes"), (4096 - 256 - 1024 - 128) * kMiB);
}

TEST(PatchCacheBudget, EvictionsAreCountedAndTheNextRequestPreprocessesAgain) {
  TempDir dir;
  double oneSet = 0;
  {
    TempDir sizing;  // a server and store of its own
    auto server = ServerProcess::start(sizing.path(), {});
    ASSERT_TRUE(server);
    uploadAndTessellate(*server, "a", 24, true);
    oneSet = seriesValue(metricsOf(*server), "tessera_patch_cache_bytes");
    ASSERT_GT(oneSet, 0);
  }
  // Room for one of the two grids' patch sets (about the same size; two topologies, so that the
  // cache keeps no topology, patch_set_cache.h).
  auto server = ServerProcess::start(dir.path(), {"--patch-cache-bytes", std::to_string(int64_t(1.5 * oneSet))});
  ASSERT_TRUE(server);
  uploadAndTessellate(*server, "a", 24, true);
  uploadAndTessellate(*server, "b", 25, true);
  std::string metrics = metricsOf(*server);
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_evictions_total"), 1) << metrics;
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_misses_total"), 2) << metrics;
  uploadAndTessellate(*server, "a", 24, false);
  metrics = metricsOf(*server);
  // a's second patch set keeps its topology (patch_set_cache.h): the topology takes b's room, and
  // a's patch set the topology's (the budget holds one and a half patch sets).
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_evictions_total"), 3) << metrics;
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_misses_total"), 3) << metrics;
}

}  // namespace
}  // namespace tessera::test
