// Bearer-token authentication beyond the catalogue's refusals: health stays open for probes,
// the token can come from a file or the environment, and reflection is withheld.
#include <gtest/gtest.h>

#include <fstream>

#include "grpc/health/v1/health.grpc.pb.h"
#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

grpc::Status serverInfo(ServerProcess& server, const std::string& token) {
  auto stub = v1::ServerInfoService::NewStub(server.channel());
  grpc::ClientContext context;
  prepare(context, token);
  v1::ServerInfo info;
  return stub->GetServerInfo(&context, {}, &info);
}

// A reflection request listing the services (ServerReflectionRequest with list_services = "",
// field 7, encoded by hand: no reflection stubs ship with Debian's gRPC), sent with no metadata
// as one message on the bidirectional stream; OK with an answer when reflection is served.
grpc::Status listServices(ServerProcess& server, std::string& answer) {
  return rawUnaryCall(server.channel(), "/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo",
                      std::string("\x3a\x00", 2), {}, &answer);
}

TEST(Auth, ReflectionIsServedOnlyWithoutATokenAndUnlessTurnedOff) {
  TempDir dir;
  auto open = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "a.db").string()});
  auto withToken = ServerProcess::start(
      dir.path(), {"--store", "sqlite:" + (dir.path() / "b.db").string(), "--token", "s3cret"});
  auto turnedOff = ServerProcess::start(
      dir.path(), {"--store", "sqlite:" + (dir.path() / "c.db").string(), "--no-reflection"});
  ASSERT_TRUE(open && withToken && turnedOff);
  std::string answer;
  ASSERT_TRUE(listServices(*open, answer).ok());
  EXPECT_NE(answer.find("tessera.v1.MeshService"), std::string::npos);
  EXPECT_EQ(listServices(*withToken, answer).error_code(), grpc::StatusCode::UNIMPLEMENTED);
  EXPECT_NE(withToken->log().find("reflection off"), std::string::npos);
  EXPECT_EQ(listServices(*turnedOff, answer).error_code(), grpc::StatusCode::UNIMPLEMENTED);
}

TEST(Auth, HealthChecksNeedNoTokenWhileEveryOtherCallDoes) {
  TempDir dir;
  // start() itself waits for SERVING through an unauthenticated health check.
  auto server = ServerProcess::start(
      dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string(), "--token", "s3cret"});
  ASSERT_TRUE(server);
  auto health = grpc::health::v1::Health::NewStub(server->channel());
  grpc::ClientContext context;
  prepare(context);
  grpc::health::v1::HealthCheckResponse response;
  ASSERT_TRUE(health->Check(&context, {}, &response).ok());
  EXPECT_EQ(response.status(), grpc::health::v1::HealthCheckResponse::SERVING);
  EXPECT_EQ(serverInfo(*server, "").error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_TRUE(serverInfo(*server, "s3cret").ok());
}

// Load balancers and orchestrators ask health per service: each of the server's services answers
// by its full name, as the server itself ("") does, and an unknown name is NOT_FOUND.
TEST(Auth, HealthAnswersForEveryServiceByName) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string()});
  ASSERT_TRUE(server);
  auto health = grpc::health::v1::Health::NewStub(server->channel());
  for (const char* name : {"", "tessera.v1.MeshService", "tessera.v1.TessellationService", "tessera.v1.RenderService",
                           "tessera.v1.ServerInfoService", "tessera.v1.NoSuchService"}) {
    SCOPED_TRACE(name);
    grpc::ClientContext context;
    prepare(context);
    grpc::health::v1::HealthCheckRequest request;
    request.set_service(name);
    grpc::health::v1::HealthCheckResponse response;
    const grpc::Status status = health->Check(&context, request, &response);
    if (std::string(name) == "tessera.v1.NoSuchService") {
      EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
    } else {
      ASSERT_TRUE(status.ok()) << status.error_message();
      EXPECT_EQ(response.status(), grpc::health::v1::HealthCheckResponse::SERVING);
    }
  }
}

// A server that other machines can reach says so at start when it has no token. (The server
// listens on every address here, but the test talks to none of them.)
TEST(Auth, ListeningBeyondLoopbackWithoutATokenIsWarnedAbout) {
  TempDir dir;
  const std::string warning = "reachable from other machines and no --token is set";
  auto open = ServerProcess::start(dir.path(), {"--listen", "0.0.0.0:0"}, {}, /*awaitServing=*/false);
  ASSERT_TRUE(open);
  EXPECT_NE(open->log().find(warning), std::string::npos) << open->log();
  open->terminate();
  auto withToken = ServerProcess::start(dir.path(), {"--listen", "0.0.0.0:0", "--token", "T"}, {}, false);
  ASSERT_TRUE(withToken);
  EXPECT_EQ(withToken->log().find(warning), std::string::npos) << withToken->log();
  withToken->terminate();
  auto loopback = ServerProcess::start(dir.path(), {});
  ASSERT_TRUE(loopback);
  EXPECT_EQ(loopback->log().find(warning), std::string::npos) << loopback->log();
}

TEST(Auth, TheTokenCanComeFromAFileOrTheEnvironment) {
  TempDir dir;
  std::filesystem::path tokenFile = dir.path() / "token";
  std::ofstream(tokenFile) << "from-file\n";
  auto fromFile = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "a.db").string(),
                                                    "--token-file", tokenFile.string()});
  auto fromEnv = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "b.db").string()},
                                      {{"TESSERA_TOKEN", "from-env"}});
  ASSERT_TRUE(fromFile && fromEnv);
  EXPECT_TRUE(serverInfo(*fromFile, "from-file").ok());
  EXPECT_EQ(serverInfo(*fromFile, "from-env").error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_TRUE(serverInfo(*fromEnv, "from-env").ok());
  EXPECT_EQ(serverInfo(*fromEnv, "").error_code(), grpc::StatusCode::UNAUTHENTICATED);
}

}  // namespace
}  // namespace tessera::test
