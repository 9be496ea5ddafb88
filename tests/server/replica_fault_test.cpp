// Replicas that survive each other: three tessera-server processes on one PostgreSQL database
// behind one client channel with the CLI's service config (proto/tessera/v1/service_config.json: round_robin,
// transparent retries of UNAVAILABLE). Under a steady mix of uploads, reads and tessellations,
// one server gets SIGTERM (graceful drain) and another SIGKILL. The client may retry a call that
// ended UNAVAILABLE (its server vanished mid-call); every other outcome is a failure, and every
// upload the client saw acknowledged must be readable afterwards. Skipped without
// TESSERA_TEST_POSTGRES_URL (tools/test.sh starts a cluster). The figures it prints are recorded
// in bench/REPLICA-RESULTS.md.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <sstream>
#include <thread>

#include "tessera/service_config.h"
#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kClients = 4;
constexpr int kAppAttempts = 5;  // a call that ends UNAVAILABLE is retried this often by the caller
constexpr auto kLoad = std::chrono::seconds(9);
constexpr auto kTerminateAt = std::chrono::seconds(3);
constexpr auto kKillAt = std::chrono::seconds(5);

struct Tally {
  std::mutex mutex;
  int64_t calls = 0, appRetries = 0;
  std::vector<std::string> failures;  // "method: CODE message"
  std::vector<std::string> acknowledged;
  std::vector<double> latencyMs;
};

std::shared_ptr<grpc::Channel> balancedChannel(const std::vector<const ServerProcess*>& servers) {
  std::string target = "ipv4:";
  for (const ServerProcess* s : servers) target += (target.size() > 5 ? "," : "") + s->address();
  grpc::ChannelArguments arguments;
  arguments.SetServiceConfigJSON(kClientServiceConfig);
  return grpc::CreateCustomChannel(target, grpc::InsecureChannelCredentials(), arguments);
}

// One call with the caller's retries of UNAVAILABLE; a failure of any other kind is recorded.
template <typename Call>
void attempt(Tally& tally, const char* method, Call call) {
  const auto start = Clock::now();
  grpc::Status status = call();
  int retries = 0;
  while (status.error_code() == grpc::StatusCode::UNAVAILABLE && retries + 1 < kAppAttempts) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    status = call();
    ++retries;
  }
  std::lock_guard lock(tally.mutex);
  ++tally.calls;
  tally.appRetries += retries;
  tally.latencyMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  if (!status.ok()) tally.failures.push_back(std::string(method) + ": " + std::to_string(status.error_code()) + " " + status.error_message());
}

void client(int index, const std::shared_ptr<grpc::Channel>& channel, Clock::time_point end, Tally& tally) {
  auto meshes = v1::MeshService::NewStub(channel);
  auto tessellation = v1::TessellationService::NewStub(channel);
  for (int round = 0; Clock::now() < end; ++round) {
    const std::string id = "load-" + std::to_string(index) + "-" + std::to_string(round);
    bool stored = false;
    attempt(tally, "UploadMesh", [&] {
      UploadResult result = uploadMessages(*meshes, arraysUpload(id, gridMesh(4, index * 1000 + round)));
      // A retry of an upload that did commit finds its id taken: the mesh is there.
      if (result.status.error_code() == grpc::StatusCode::ALREADY_EXISTS) result.status = grpc::Status::OK;
      stored = result.status.ok();
      return result.status;
    });
    if (!stored) continue;  // its failure is counted; there is nothing to read
    {
      std::lock_guard lock(tally.mutex);
      tally.acknowledged.push_back(id);
    }
    attempt(tally, "GetMesh", [&] {
      grpc::ClientContext context;
      prepare(context);
      v1::GetMeshRequest request;
      request.set_name("meshes/" + id);
      v1::Mesh mesh;
      return meshes->GetMesh(&context, request, &mesh);
    });
    attempt(tally, "Tessellate", [&] {
      v1::TessellateRequest request;
      request.set_name("meshes/" + id);
      request.set_relative(1e-2);
      return tessellateOverGrpc(*tessellation, request).status;
    });
  }
}

TEST(ReplicaFaults, ACallerLosesNothingWhenOneReplicaDrainsAndAnotherDies) {
  std::string whyNot;
  std::unique_ptr<PostgresDatabase> database = PostgresDatabase::create(&whyNot);
  if (!database) GTEST_SKIP() << "replica fault test skipped: " << whyNot;
  TempDir dir;
  std::vector<std::unique_ptr<ServerProcess>> servers;
  for (int i = 0; i < 3; ++i) {
    servers.push_back(ServerProcess::start(
        dir.path(), {"--store", database->url(), "--drain-delay", "1", "--shutdown-grace", "5"}));
    ASSERT_TRUE(servers.back());
  }
  auto channel = balancedChannel({servers[0].get(), servers[1].get(), servers[2].get()});
  Tally tally;
  const auto start = Clock::now();
  std::vector<std::thread> clients;
  for (int i = 0; i < kClients; ++i) clients.emplace_back(client, i, channel, start + kLoad, std::ref(tally));
  std::this_thread::sleep_until(start + kTerminateAt);
  ::kill(servers[1]->pid(), SIGTERM);  // drains: NOT_SERVING, running calls finish, new ones refused
  std::this_thread::sleep_until(start + kKillAt);
  servers[2]->kill9();
  for (std::thread& t : clients) t.join();
  const int drainedExit = servers[1]->terminate();

  // Every acknowledged upload is there, read through the survivor.
  auto survivor = v1::MeshService::NewStub(servers[0]->channel());
  int missing = 0;
  for (const std::string& id : tally.acknowledged) {
    grpc::Status status;
    downloadMesh(*survivor, id, &status);
    missing += !status.ok();
  }
  std::sort(tally.latencyMs.begin(), tally.latencyMs.end());
  const auto percentile = [&](double p) { return tally.latencyMs[size_t(p * double(tally.latencyMs.size() - 1))]; };
  std::printf("replica faults: %lld calls by %d clients in %lld s over 3 servers (SIGTERM at %lld s, SIGKILL at "
              "%lld s): %zu failed, %lld retried by the caller after UNAVAILABLE, %zu uploads acknowledged, %d "
              "missing; latency p50 %.1f ms, p99 %.1f ms, max %.1f ms; the drained server exited %d\n",
              (long long)tally.calls, kClients, (long long)kLoad.count(), (long long)kTerminateAt.count(),
              (long long)kKillAt.count(), tally.failures.size(), (long long)tally.appRetries, tally.acknowledged.size(),
              missing, percentile(0.5), percentile(0.99), tally.latencyMs.back(), drainedExit);
  for (const std::string& f : tally.failures) ADD_FAILURE() << f;
  if (!tally.failures.empty()) {
    for (size_t i = 0; i < servers.size(); ++i) {
      std::istringstream log(servers[i]->log());
      for (std::string line; std::getline(log, line);) {
        if (line.find("status=OK") == std::string::npos && line.find("method=") != std::string::npos)
          std::printf("server %zu: %s\n", i, line.c_str());
        if (line.find("signal") != std::string::npos || line.find("stopped") != std::string::npos)
          std::printf("server %zu: %s\n", i, line.c_str());
      }
    }
  }
  EXPECT_EQ(missing, 0);
  EXPECT_EQ(drainedExit, 0) << "a drained server exits cleanly";
  EXPECT_GT(tally.calls, 30) << "too little load to say anything";
}

}  // namespace
}  // namespace tessera::test
