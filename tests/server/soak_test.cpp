// A short run of the memory soak (tools/soak, tools/soak.sh: bench/SOAK-RESULTS.md has the ten
// minutes): hostile and normal clients against the real server under a 3 GiB budget. Every
// request ends with a code it may end with, every normal request is served (after waiting out
// pushbacks), the server's peak resident memory stays within its budget, and what the run leaves
// resident afterwards is bounded.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

TEST(SoakTest, HostileAndNormalClientsUnderABudget) {
  TempDir dir;
  constexpr int64_t kBudget = int64_t(3) << 30;
  auto server = ServerProcess::start(
      dir.path(), {"--memory-budget", "3GiB", "--cache-bytes", "256MiB", "--patch-cache-bytes", "256MiB"});
  ASSERT_TRUE(server);
  const auto json = dir.path() / "soak.json", output = dir.path() / "soak.md";
  const std::string command = std::string(TESSERA_SOAK_BINARY) + " --server " + server->address() +
                              " --server-pid " + std::to_string(server->pid()) + " --models " + TESSERA_MODELS_DIR +
                              " --clients 8 --hostile 3 --seconds 20 --json " + json.string() + " > " +
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
  // What stays resident after the run beyond the caches (the patch sets were built before
  // "before"): thread arenas, the renderer's pools (bench/SOAK-RESULTS.md); bounded, not growing.
  EXPECT_LE(r["rss_after_bytes"].get<int64_t>() - r["rss_before_bytes"].get<int64_t>(), int64_t(256) << 20);
  bool refusedHuge = false;
  for (const auto& answer : r["answers"]) {
    refusedHuge |= answer["kind"] == "uniform level 40" && answer["code"] == "RESOURCE_EXHAUSTED";
  }
  EXPECT_TRUE(refusedHuge) << report;
}

}  // namespace
}  // namespace tessera::test
