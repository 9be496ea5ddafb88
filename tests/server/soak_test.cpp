// A short run of the memory soak (tools/soak, tools/soak.sh: bench/SOAK-RESULTS.md has the ten
// minutes): hostile, cold-storm and normal clients against the real server under a 3 GiB budget.
// Every request ends with a code it may end with (a cold one OK, or RESOURCE_EXHAUSTED with a
// message), every normal request is served (after waiting out pushbacks) while the storm uploads
// meshes the server has never seen, each of which it preprocesses, the server's peak resident
// memory stays within its budget, and what the run leaves resident afterwards is bounded. Each
// hostile client starts and ends with runaways (bigguy at 1e-5, seconds of work under load, with
// a 1 s deadline): once every client has its answers the server's CPU is idle within 2 s, and
// again after one more alone with a 0.3 s deadline.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

TEST(SoakTest, HostileColdStormAndNormalClientsUnderABudget) {
  TempDir dir;
  constexpr int64_t kBudget = int64_t(3) << 30;
  auto server = ServerProcess::start(
      dir.path(), {"--memory-budget", "3GiB", "--cache-bytes", "256MiB", "--patch-cache-bytes", "256MiB"});
  ASSERT_TRUE(server);
  const auto json = dir.path() / "soak.json", output = dir.path() / "soak.md";
  const std::string command = std::string(TESSERA_SOAK_BINARY) + " --server " + server->address() +
                              " --server-pid " + std::to_string(server->pid()) + " --models " + TESSERA_MODELS_DIR +
                              " --clients 10 --hostile 3 --cold 2 --seconds 20 --json " + json.string() + " > " +
                              output.string() + " 2>&1";
  const int status = std::system(command.c_str());
  const std::string report = readFile(output);
  std::printf("%s\n", report.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << report << server->log();

  const nlohmann::json r = nlohmann::json::parse(readFile(json));
  EXPECT_EQ(r["unexpected"].get<int>(), 0);
  EXPECT_TRUE(r["last_request_ok"].get<bool>());
  EXPECT_GT(r["normal"]["requests"].get<int>(), 0);
  EXPECT_EQ(r["normal"]["ok"].get<int>(), r["normal"]["requests"].get<int>());
  EXPECT_EQ(r["memory_budget_bytes"].get<int64_t>(), kBudget);
  // The budget covers the caches, the jobs and 128 MiB for the server itself.
  EXPECT_LE(r["peak_rss_bytes"].get<int64_t>(), kBudget);
  // What stays resident after the run beyond what the caches hold (the small and large models'
  // patch sets were built before "before"; the cold storm's fill the caches during the run):
  // thread arenas, the renderer's pools (bench/SOAK-RESULTS.md); bounded, not growing.
  const std::string metrics = httpGet(server->metricsAddress(), "/metrics");
  const double cached = seriesValue(metrics, "tessera_patch_cache_bytes") + seriesValue(metrics, "tessera_cache_bytes");
  EXPECT_LE(r["rss_after_bytes"].get<int64_t>() - r["rss_before_bytes"].get<int64_t>(),
            (int64_t(256) << 20) + int64_t(cached));

  // The storm was cold: every copy it uploaded had content of its own, and the server
  // preprocessed at least once per first GLB it delivered (its patch-set cache misses; the
  // warm-up, hostile requests and evicted patch sets add more).
  const nlohmann::json& cold = r["cold"];
  EXPECT_GT(cold["first_glbs_ok"].get<int>(), 0) << report;
  EXPECT_EQ(cold["distinct_contents"].get<int>(), cold["uploads_ok"].get<int>()) << report;
  EXPECT_GE(seriesValue(metrics, "tessera_patch_cache_misses_total"), cold["first_glbs_ok"].get<double>()) << metrics;
  bool refusedHuge = false;
  int runaways = 0;
  for (const auto& answer : r["answers"]) {
    refusedHuge |= answer["kind"] == "uniform level 40" && answer["code"] == "RESOURCE_EXHAUSTED";
    if (answer["kind"] == "runaway 1e-5 (1 s deadline)") runaways += answer["count"].get<int>();
  }
  EXPECT_TRUE(refusedHuge) << report;
  EXPECT_GE(runaways, 3) << report;
  EXPECT_GE(r["server_idle_after_s"].get<double>(), 0) << report;
  EXPECT_LE(r["server_idle_after_s"].get<double>(), 2.0) << report;
  EXPECT_GE(r["runaway_idle_after_s"].get<double>(), 0) << report;
  EXPECT_LE(r["runaway_idle_after_s"].get<double>(), 2.0) << report;
}

}  // namespace
}  // namespace tessera::test
