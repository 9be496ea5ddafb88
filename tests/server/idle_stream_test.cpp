// Clients that open streams and then stall them: a stream whose client sends (or reads) nothing
// for --stream-idle-timeout is cancelled, and past --max-open-streams new streaming calls are
// refused at once, so that idle streams cannot take the threads that other calls need.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

using Clock = std::chrono::steady_clock;

// An UploadMesh stream held open: started (its call reaches the server) and sending nothing.
struct IdleUpload {
  grpc::ClientContext context;
  v1::Mesh response;
  std::unique_ptr<grpc::ClientWriter<v1::UploadMeshRequest>> writer;

  IdleUpload(v1::MeshService::Stub& stub, int seconds, const std::string& token = {}) {
    prepare(context, token, seconds);
    writer = stub.UploadMesh(&context, &response);
  }
};

TEST(IdleStreams, AnUploadWhoseClientSendsNothingIsCancelled) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--stream-idle-timeout", "1"});
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  const auto start = Clock::now();
  IdleUpload idle(*stub, 60);
  ASSERT_TRUE(idle.writer->Write(headerMessage("stalled", v1::MESH_FORMAT_OBJ, 1000)));
  const grpc::Status status = idle.writer->Finish();
  const double waited = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::CANCELLED) << status.error_message();
  EXPECT_GT(waited, 0.9);
  EXPECT_LT(waited, 10);
  EXPECT_NE(server->log().find("UploadMesh from"), std::string::npos) << server->log();
  EXPECT_NE(server->log().find("sent nothing for 1 s: call cancelled"), std::string::npos) << server->log();
  EXPECT_EQ(seriesValue(httpGet(server->metricsAddress(), "/metrics"), "tessera_streams_cancelled_total"), 1);
  // A client that keeps sending is not cut off.
  EXPECT_TRUE(uploadMessages(*stub, arraysUpload("busy", gridMesh(4, 0))).status.ok());
}

TEST(IdleStreams, ADownloadWhoseClientReadsNothingIsCancelled) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--stream-idle-timeout", "1"});
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  // Megabytes of arrays: more than the flow-control windows hold, so the server's writes wait.
  ASSERT_TRUE(uploadMessages(*stub, arraysUpload("large", gridMesh(500, 0))).status.ok());
  // The reading client's window stays at gRPC's 64 KiB: left to probe the bandwidth, gRPC grew it
  // past the whole download on a loaded machine, and the server never had to wait.
  grpc::ChannelArguments fixedWindow;
  fixedWindow.SetInt(GRPC_ARG_HTTP2_BDP_PROBE, 0);
  auto reading = v1::MeshService::NewStub(
      grpc::CreateCustomChannel(server->address(), grpc::InsecureChannelCredentials(), fixedWindow));
  grpc::ClientContext context;
  prepare(context, {}, 60);
  v1::DownloadMeshRequest request;
  request.set_name("meshes/large");
  auto reader = reading->DownloadMesh(&context, request);
  v1::DownloadMeshResponse message;
  ASSERT_TRUE(reader->Read(&message));
  std::this_thread::sleep_for(std::chrono::seconds(4));
  while (reader->Read(&message)) {
  }
  const grpc::Status status = reader->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::CANCELLED) << status.error_message();
  EXPECT_NE(server->log().find("DownloadMesh from"), std::string::npos) << server->log();
  EXPECT_NE(server->log().find("read nothing for 1 s: call cancelled"), std::string::npos) << server->log();
}

TEST(IdleStreams, PastTheOpenStreamLimitStreamsAreRefusedAndUnaryCallsStillServed) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--max-open-streams", "3"});
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  std::vector<std::unique_ptr<IdleUpload>> held;
  for (int i = 0; i < 3; ++i) held.push_back(std::make_unique<IdleUpload>(*stub, 60));
  const auto giveUp = Clock::now() + std::chrono::seconds(20);
  while (seriesValue(httpGet(server->metricsAddress(), "/metrics"), "tessera_open_streams") < 3 && Clock::now() < giveUp) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_EQ(seriesValue(httpGet(server->metricsAddress(), "/metrics"), "tessera_open_streams"), 3);

  const auto start = Clock::now();
  const UploadResult refused = uploadMessages(*stub, arraysUpload("fourth", gridMesh(4, 0)));
  EXPECT_EQ(refused.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(refused.status.error_message().find("3 streaming calls open"), std::string::npos)
      << refused.status.error_message();
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 5);

  grpc::ClientContext context;
  prepare(context);
  v1::ListMeshesResponse list;
  EXPECT_TRUE(stub->ListMeshes(&context, {}, &list).ok());

  // Once the held streams end, streams are served again.
  for (auto& upload : held) upload->context.TryCancel();
  held.clear();
  const auto reopen = Clock::now() + std::chrono::seconds(20);
  UploadResult accepted;
  do {
    accepted = uploadMessages(*stub, arraysUpload("fifth", gridMesh(4, 0)));
  } while (accepted.status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED && Clock::now() < reopen);
  EXPECT_TRUE(accepted.status.ok()) << accepted.status.error_message();
}

// The reproducer of a token-protected server stopped by anyone: 600 streams opened without the
// token and left idle. Each is refused as it arrives and holds nothing.
TEST(IdleStreams, UnauthenticatedStreamsHoldNothing) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--token", "T", "--max-open-streams", "16"});
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  std::vector<std::unique_ptr<IdleUpload>> strangers;
  for (int i = 0; i < 600; ++i) strangers.push_back(std::make_unique<IdleUpload>(*stub, 60, "wrong"));

  grpc::ClientContext context;
  prepare(context, "T");
  v1::ListMeshesResponse list;
  EXPECT_TRUE(stub->ListMeshes(&context, {}, &list).ok());
  EXPECT_TRUE(uploadMessages(*stub, arraysUpload("owner", gridMesh(4, 0)), "T").status.ok());
  EXPECT_EQ(seriesValue(httpGet(server->metricsAddress(), "/metrics"), "tessera_open_streams"), 0);
  for (auto& stranger : strangers) {
    EXPECT_EQ(stranger->writer->Finish().error_code(), grpc::StatusCode::UNAUTHENTICATED);
  }
}

}  // namespace
}  // namespace tessera::test
