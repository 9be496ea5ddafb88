// A store that fails under the server: the client hears UNAVAILABLE (retry later) and nothing of
// the store's own words (its library's messages, file names), which go to the server's log; the
// health service says NOT_SERVING while the store cannot serve, and SERVING once it can again.
#include <gtest/gtest.h>

#include <signal.h>

#include <fstream>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

grpc::Status listMeshes(ServerProcess& server) {
  auto stub = v1::MeshService::NewStub(server.channel());
  grpc::ClientContext context;
  prepare(context);
  v1::ListMeshesRequest request;
  v1::ListMeshesResponse response;
  return stub->ListMeshes(&context, request, &response);
}

// SQLite's pages after the first (which holds the schema) overwritten while the server is down:
// it starts, and every query of the meshes fails inside SQLite.
TEST(StoreFailure, ADamagedSqliteStoreIsUnavailableWithoutItsInternals) {
  TempDir dir;
  const std::filesystem::path database = dir.path() / "damaged.db";
  {
    auto server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + database.string()});
    ASSERT_TRUE(server);
    auto stub = v1::MeshService::NewStub(server->channel());
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(uploadMessages(*stub, arraysUpload("mesh-" + std::to_string(i), gridMesh(6, 0))).status.ok());
    }
    ASSERT_EQ(server->terminate(), 0);
  }
  const auto size = std::filesystem::file_size(database);
  ASSERT_GT(size, 8192u);
  {
    std::fstream file(database, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(4096);
    const std::string garbage(size - 4096, '\xA5');
    file.write(garbage.data(), std::streamsize(garbage.size()));
  }
  auto server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + database.string()}, {},
                                     /*awaitServing=*/false);
  ASSERT_TRUE(server);
  EXPECT_TRUE(waitForHealth(server->channel(), kNotServing));
  EXPECT_TRUE(waitForHealth(server->channel(), kNotServing, "tessera.v1.TessellationService"));
  const grpc::Status status = listMeshes(*server);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAVAILABLE) << status.error_message();
  EXPECT_NE(status.error_message().find("mesh store unavailable"), std::string::npos) << status.error_message();
  for (const std::string& internal : std::vector<std::string>{"sqlite", "malformed", "damaged.db", dir.path().string()}) {
    EXPECT_EQ(status.error_message().find(internal), std::string::npos) << status.error_message();
  }
  // The cause is in the server's log for its operator.
  EXPECT_NE(server->log().find("malformed"), std::string::npos);
  EXPECT_NE(server->log().find("health NOT_SERVING"), std::string::npos);
}

// A PostgreSQL store taken away while the server runs (its connections ended, its database
// renamed) and given back: health follows, and calls in between are UNAVAILABLE.
TEST(StoreFailure, HealthFollowsAPostgresOutage) {
  std::string whyNot;
  auto database = PostgresDatabase::create(&whyNot);
  if (!database) GTEST_SKIP() << "PostgreSQL store test skipped: " << whyNot;
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--store", database->url()});
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  ASSERT_TRUE(uploadMessages(*stub, arraysUpload("kept", gridMesh(4, 0))).status.ok());

  ASSERT_EQ(database->takeAway(), "");
  EXPECT_TRUE(waitForHealth(server->channel(), kNotServing)) << server->log();
  EXPECT_EQ(listMeshes(*server).error_code(), grpc::StatusCode::UNAVAILABLE);

  ASSERT_EQ(database->giveBack(), "");
  EXPECT_TRUE(waitForHealth(server->channel(), kServing)) << server->log();
  EXPECT_TRUE(listMeshes(*server).ok());
  EXPECT_NE(server->log().find("health SERVING"), std::string::npos);
}

// A frozen PostgreSQL: the backends serving the server's connections stopped (SIGSTOP), as a
// database that accepts a connection and never answers. Calls end within the store's timeout
// (UNAVAILABLE on a frozen connection, or OK on a fresh one), never at the client's deadline, and
// the frozen connections are dropped.
TEST(StoreFailure, AFrozenPostgresCannotHoldCallsPastTheStoreTimeout) {
  std::string whyNot;
  auto database = PostgresDatabase::create(&whyNot);
  if (!database) GTEST_SKIP() << "PostgreSQL store test skipped: " << whyNot;
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {"--store", database->url(), "--store-timeout", "1"});
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  ASSERT_TRUE(uploadMessages(*stub, arraysUpload("kept", gridMesh(4, 0))).status.ok());

  const std::vector<int> frozen = database->sessions();
  ASSERT_FALSE(frozen.empty());
  for (int pid : frozen) ASSERT_EQ(::kill(pid, SIGSTOP), 0);
  for (int call = 0; call < 3; ++call) {
    grpc::ClientContext context;
    prepare(context, {}, 20);
    v1::GetMeshRequest request;
    request.set_name("meshes/kept");
    v1::Mesh mesh;
    const grpc::Status status = stub->GetMesh(&context, request, &mesh);
    EXPECT_TRUE(status.ok() || status.error_code() == grpc::StatusCode::UNAVAILABLE)
        << int(status.error_code()) << ": " << status.error_message();
  }
  for (int pid : frozen) ::kill(pid, SIGCONT);
  EXPECT_NE(server->log().find("no answer within 1000 ms"), std::string::npos) << server->log();
  EXPECT_TRUE(waitForHealth(server->channel(), kServing));
}

}  // namespace
}  // namespace tessera::test
