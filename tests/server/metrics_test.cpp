// The Prometheus endpoint: text format over HTTP, counting requests by method and status code,
// upload bytes, cache use and store size.
#include <gtest/gtest.h>

#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <regex>
#include <thread>

#include "core/base/version.h"
#include "grpc/health/v1/health.grpc.pb.h"
#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

TEST(Metrics, ScrapesCountRequestsByMethodAndStatusAndTrackUploadsAndTheStore) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string()});
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  MeshArrays mesh = gridMesh(3, 0);
  ASSERT_TRUE(uploadMessages(*stub, arraysUpload("counted", mesh)).status.ok());
  for (int i = 0; i < 2; ++i) {
    grpc::ClientContext context;
    prepare(context);
    v1::GetMeshRequest request;
    request.set_name("meshes/missing");
    v1::Mesh out;
    ASSERT_EQ(stub->GetMesh(&context, request, &out).error_code(), grpc::StatusCode::NOT_FOUND);
  }
  grpc::Status status;
  downloadMesh(*stub, "counted", &status);  // served from the cache filled by the upload

  std::string response = httpGet(server->metricsAddress(), "/metrics");

  ASSERT_NE(response.find("HTTP/1.1 200 OK"), std::string::npos) << response;
  EXPECT_NE(response.find("Content-Type: text/plain; version=0.0.4"), std::string::npos);
  EXPECT_EQ(seriesValue(response, "tessera_requests_total{method=\"/tessera.v1.MeshService/GetMesh\","
                                  "code=\"NOT_FOUND\"}"),
            2);
  EXPECT_EQ(seriesValue(response, "tessera_requests_total{method=\"/tessera.v1.MeshService/UploadMesh\","
                                  "code=\"OK\"}"),
            1);
  EXPECT_EQ(seriesValue(response, "tessera_request_duration_seconds_count{method="
                                  "\"/tessera.v1.MeshService/GetMesh\"}"),
            2);
  EXPECT_EQ(seriesValue(response, "tessera_upload_bytes_total"), double(mesh.uploadBytes()));
  EXPECT_EQ(seriesValue(response, "tessera_cache_hits_total"), 1);
  EXPECT_EQ(seriesValue(response, "tessera_store_meshes"), 1);
  EXPECT_EQ(seriesValue(response, "tessera_store_bytes"), double(canonicalEncoding(mesh).size()));
  EXPECT_EQ(seriesValue(response, "tessera_queue_depth"), 0);
  EXPECT_EQ(seriesValue(response, "tessera_triangles_produced_total"), 0);
}

// Calls to methods the server does not serve share one label, however many names clients make up.
TEST(Metrics, MadeUpMethodNamesShareOneLabel) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string()});
  ASSERT_TRUE(server);
  for (int i = 0; i < 20; ++i) {
    const grpc::Status status = rawUnaryCall(server->channel(), "/made.up.Service/Method" + std::to_string(i), "");
    ASSERT_EQ(status.error_code(), grpc::StatusCode::UNIMPLEMENTED);
  }
  const std::string response = httpGet(server->metricsAddress(), "/metrics");
  EXPECT_EQ(response.find("made.up.Service"), std::string::npos);
  EXPECT_EQ(seriesValue(response, "tessera_requests_total{method=\"unknown\",code=\"UNIMPLEMENTED\"}"), 20);
}

// A TCP connection to `address` (HOST:PORT, loopback in these tests); -1 if it cannot connect.
int connectTo(const std::string& address) {
  const size_t colon = address.rfind(':');
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(address.substr(0, colon).c_str(), address.substr(colon + 1).c_str(), &hints, &found) != 0) return -1;
  int fd = socket(found->ai_family, SOCK_STREAM, 0);
  if (fd >= 0 && connect(fd, found->ai_addr, found->ai_addrlen) != 0) close(fd), fd = -1;
  freeaddrinfo(found);
  return fd;
}

// Clients that trickle a request a byte at a time hold only their own connections: a scrape
// beside them is answered at once, and they are dropped once their two seconds are up.
TEST(Metrics, SlowClientsDoNotHoldUpAScrape) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string()});
  ASSERT_TRUE(server);
  std::vector<int> slow;
  for (int i = 0; i < 3; ++i) slow.push_back(connectTo(server->metricsAddress()));
  const std::string request = "GET /metrics HTTP/1.1\r\n";
  for (size_t b = 0; b < 4; ++b) {
    for (int fd : slow) ASSERT_EQ(send(fd, &request[b], 1, MSG_NOSIGNAL), 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const std::string response = httpGet(server->metricsAddress(), "/metrics");
  EXPECT_NE(response.find("HTTP/1.1 200 OK"), std::string::npos);
  // Answered while the slow clients are still connected (a server serving one connection at a
  // time reaches the scrape only after dropping them).
  for (int fd : slow) {
    char byte;
    EXPECT_EQ(recv(fd, &byte, 1, MSG_DONTWAIT), -1) << "a slow client was dropped before the scrape was answered";
  }
  // Past their deadline the slow connections are closed: a read sees the end of the stream.
  for (int fd : slow) {
    timeval wait{5, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &wait, sizeof wait);
    char byte;
    EXPECT_EQ(recv(fd, &byte, 1, 0), 0);
    close(fd);
  }
}

// A "Key:   value kB"-style field of /proc/PID/status or a row of /proc/PID/limits, read by the
// test itself: the kernel's own accounting, beside the server's reading of /proc/self/stat.
double procField(pid_t pid, const std::string& file, const std::string& key, int column) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/" + file);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key, 0) != 0) continue;
    std::istringstream fields(line.substr(key.size()));
    std::string value;
    for (int c = 0; c <= column; ++c) fields >> value;
    return std::stod(value);
  }
  return -1;
}

// What every Prometheus client exports about its process, and the build, against what the
// kernel says of the server's process (read here from /proc/PID) and what the test was built with.
TEST(Metrics, ExportProcessMetricsAndBuildInfo) {
  TempDir dir;
  const double startedAfter =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count() - 2;
  auto server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string()});
  ASSERT_TRUE(server);
  const std::string page = httpGet(server->metricsAddress(), "/metrics");
  const pid_t pid = server->pid();
  const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();

  const std::regex info(R"re(\ntessera_build_info\{version="([^"]*)",grpc="([^"]*)",compiler="[^"]+"\} 1\n)re");
  std::smatch found;
  ASSERT_TRUE(std::regex_search(page, found, info)) << page;
  EXPECT_EQ(found[1], kVersion);
  EXPECT_EQ(found[2], grpc::Version());

  const double resident = seriesValue(page, "process_resident_memory_bytes");
  const double kernelResident = procField(pid, "status", "VmRSS:", 0) * 1024;
  EXPECT_GT(resident, 1 << 20);
  EXPECT_NEAR(resident, kernelResident, 0.25 * kernelResident);
  const double virtualBytes = seriesValue(page, "process_virtual_memory_bytes");
  const double kernelVirtual = procField(pid, "status", "VmSize:", 0) * 1024;
  EXPECT_NEAR(virtualBytes, kernelVirtual, 0.25 * kernelVirtual);
  EXPECT_GE(virtualBytes, resident);

  const double start = seriesValue(page, "process_start_time_seconds");
  EXPECT_GE(start, startedAfter);
  EXPECT_LE(start, now + 1);
  const double cpu = seriesValue(page, "process_cpu_seconds_total");
  EXPECT_GE(cpu, 0);
  EXPECT_LE(cpu, (now - startedAfter) * std::thread::hardware_concurrency());

  size_t kernelFds = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/fd")) {
    ++kernelFds;
  }
  EXPECT_NEAR(seriesValue(page, "process_open_fds"), double(kernelFds), 4);
  EXPECT_EQ(seriesValue(page, "process_max_fds"), procField(pid, "limits", "Max open files", 0));
}

// A client that gives up on a call (its deadline passes, or it cancels) is counted under the code
// the client saw, not UNKNOWN: here a Health/Watch stream that the server keeps open.
TEST(Metrics, CallsTheClientAbandonsAreCountedByWhatItSaw) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string()});
  ASSERT_TRUE(server);
  auto stub = grpc::health::v1::Health::NewStub(server->channel());
  grpc::health::v1::HealthCheckRequest request;
  {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::milliseconds(300));
    auto watch = stub->Watch(&context, request);
    grpc::health::v1::HealthCheckResponse response;
    while (watch->Read(&response)) {
    }
    ASSERT_EQ(watch->Finish().error_code(), grpc::StatusCode::DEADLINE_EXCEEDED);
  }
  {
    grpc::ClientContext context;
    auto watch = stub->Watch(&context, request);
    grpc::health::v1::HealthCheckResponse response;
    ASSERT_TRUE(watch->Read(&response));
    context.TryCancel();
    while (watch->Read(&response)) {
    }
    ASSERT_EQ(watch->Finish().error_code(), grpc::StatusCode::CANCELLED);
  }
  const std::string method = "tessera_requests_total{method=\"/grpc.health.v1.Health/Watch\",code=";
  // The call whose deadline passed can end on the server as either (its own deadline, or the
  // client's cancellation arriving first): a series the page lacks (-1) counts as none.
  auto abandoned = [&method](const std::string& page) {
    return std::max(0.0, seriesValue(page, method + "\"DEADLINE_EXCEEDED\"}")) +
           std::max(0.0, seriesValue(page, method + "\"CANCELLED\"}"));
  };
  std::string page;
  for (int attempt = 0; attempt < 50; ++attempt) {  // the server learns of the ends a little later
    page = httpGet(server->metricsAddress(), "/metrics");
    if (abandoned(page) >= 2) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_EQ(seriesValue(page, method + "\"UNKNOWN\"}"), -1) << page;
  EXPECT_EQ(abandoned(page), 2) << page;
}

TEST(Metrics, OtherPathsAreNotFound) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string()});
  ASSERT_TRUE(server);
  EXPECT_NE(httpGet(server->metricsAddress(), "/").find("404 Not Found"), std::string::npos);
}

}  // namespace
}  // namespace tessera::test
