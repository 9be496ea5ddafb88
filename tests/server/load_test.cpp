// Sustained load on loopback with `tessera bench`: 32 concurrent clients, each on a connection of
// its own, send a few thousand requests, mostly small tessellations of bigguy, with get, list and
// info mixed in. No request may fail, the bench's counts must agree with the server's metrics,
// and the server's resident memory may grow only within a stated bound. No speed is asserted:
// the figures are printed for the log, and tools/load-test.sh measures speed.
//
// Bounded: at most kRequests requests or kDuration, whichever comes first, each call with a
// deadline. Label "load" in ctest (`ctest -LE load` leaves it out).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "tests/server/process_memory.h"
#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

constexpr int kClients = 32;
constexpr int kRequests = 3000;
constexpr const char* kDuration = "45s";
constexpr const char* kCallDeadline = "30s";
// Generous: the mesh and patch caches, gRPC's per-connection buffers and the allocator's arenas
// for 32 connections stay far below it; a leak of even a small GLB per request would not.
constexpr int64_t kMaxRssGrowthBytes = 512LL << 20;

double okCalls(const std::string& metrics, const std::string& method) {
  return seriesValue(metrics, "tessera_requests_total{method=\"" + method + "\",code=\"OK\"}");
}

// Runs a command, echoing its output to the test's log; returns the exit status.
int runEchoed(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  char buffer[4096];
  for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) std::cout.write(buffer, n);
  int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(LoadTest, ThirtyTwoClientsGetNoErrorsAndTheServerMemoryStaysBounded) {
  if (!std::filesystem::exists(TESSERA_CLI_BINARY)) {
    GTEST_SKIP() << "the tessera CLI was not built (" << TESSERA_CLI_BINARY << ")";
  }
  TempDir dir;
  // The default queue (4 per core) would refuse, by design, the tessellations of 32 clients past
  // it with RESOURCE_EXHAUSTED (tessellation_service_test covers that); this test is about
  // sustained load, so the queue holds every client.
  auto server =
      ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string(),
                                        "--max-queued-jobs", std::to_string(2 * kClients)});
  ASSERT_TRUE(server);
  auto meshes = v1::MeshService::NewStub(server->channel());
  UploadResult uploaded =
      uploadModel(*meshes, "bigguy");
  ASSERT_TRUE(uploaded.status.ok()) << uploaded.status.error_message();
  const int64_t rssBefore = processMemoryBytes(server->pid(), "VmRSS");
  ASSERT_GT(rssBefore, 0);

  const std::filesystem::path json = dir.path() / "bench.json";
  const std::string command = fmt::format(
      "env -u TESSERA_SERVER -u TESSERA_TOKEN {} --server {} bench "
      "--mix tessellate=8,get=1,list=1,info=1 --mesh meshes/bigguy --tolerance 1e-2 --relative "
      "--concurrency {} --requests {} --duration {} --timeout {} --json {}",
      TESSERA_CLI_BINARY, server->address(), kClients, kRequests, kDuration, kCallDeadline,
      json.string());
  ASSERT_EQ(runEchoed(command), 0) << command;

  const int64_t rssAfter = processMemoryBytes(server->pid(), "VmRSS");
  const int64_t peak = processMemoryBytes(server->pid(), "VmHWM");
  std::cout << fmt::format("server VmRSS {:.1f} MiB before, {:.1f} MiB after; VmHWM {:.1f} MiB\n",
                           rssBefore / 1048576.0, rssAfter / 1048576.0, peak / 1048576.0);
  RecordProperty("rss_before_bytes", std::to_string(rssBefore));
  RecordProperty("rss_after_bytes", std::to_string(rssAfter));
  RecordProperty("rss_peak_bytes", std::to_string(peak));
  EXPECT_LT(rssAfter - rssBefore, kMaxRssGrowthBytes);

  nlohmann::json results = nlohmann::json::parse(readFile(json));
  ASSERT_EQ(results["levels"].size(), 1u);
  const nlohmann::json& level = results["levels"][0];
  EXPECT_EQ(level["concurrency"], kClients);
  EXPECT_GT(level["requests"].get<int64_t>(), 0);
  EXPECT_EQ(level["ok"], level["requests"]);
  EXPECT_TRUE(level["errors"].empty()) << level["errors"].dump();
  for (const char* op : {"tessellate", "get", "list", "info"}) {
    EXPECT_GT(level["operations"][op]["ok"].get<int64_t>(), 0) << op;
  }
  RecordProperty("requests", std::to_string(level["requests"].get<int64_t>()));

  // The server counted what the bench says it sent; the bench's own setup asks for the server
  // info and the mesh once before the load. The server counts a call when gRPC releases it, a
  // little after the client has its status: poll (bounded) until the last calls are in.
  const nlohmann::json& ops = level["operations"];
  const std::map<std::string, double> expected = {
      {"/tessera.v1.TessellationService/Tessellate", ops["tessellate"]["ok"].get<double>()},
      {"/tessera.v1.MeshService/GetMesh", ops["get"]["ok"].get<double>() + 1},
      {"/tessera.v1.MeshService/ListMeshes", ops["list"]["ok"].get<double>()},
      {"/tessera.v1.ServerInfoService/GetServerInfo", ops["info"]["ok"].get<double>() + 1}};
  std::string metrics;
  auto allCounted = [&] {
    for (const auto& [method, count] : expected) {
      if (okCalls(metrics, method) != count) return false;
    }
    return true;
  };
  for (int attempt = 0; attempt < 100; ++attempt) {
    metrics = httpGet(server->metricsAddress(), "/metrics");
    if (allCounted()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  for (const auto& [method, count] : expected) EXPECT_EQ(okCalls(metrics, method), count) << method;
  EXPECT_EQ(seriesValue(metrics, "tessera_jobs_running"), 0);
  EXPECT_EQ(seriesValue(metrics, "tessera_queue_depth"), 0);
}

}  // namespace
}  // namespace tessera::test
