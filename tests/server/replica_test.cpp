// Several servers on one PostgreSQL database act as replicas: a mesh uploaded through one is
// visible, downloadable and deletable through another.
#include <gtest/gtest.h>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

TEST(PostgresReplicas, TwoServersOnOneDatabaseShareTheirMeshes) {
  std::string whyNot;
  std::unique_ptr<PostgresDatabase> database = PostgresDatabase::create(&whyNot);
  if (!database) GTEST_SKIP() << "PostgreSQL replica test skipped: " << whyNot;
  TempDir dir;
  auto first = ServerProcess::start(dir.path(), {"--store", database->url()});
  auto second = ServerProcess::start(dir.path(), {"--store", database->url()});
  ASSERT_TRUE(first && second);
  auto viaFirst = v1::MeshService::NewStub(first->channel());
  auto viaSecond = v1::MeshService::NewStub(second->channel());
  MeshArrays mesh = gridMesh(6, 4);

  UploadResult uploaded = uploadMessages(*viaFirst, arraysUpload("shared", mesh));
  ASSERT_TRUE(uploaded.status.ok()) << uploaded.status.error_message();

  grpc::Status status;
  v1::Mesh metadata;
  EXPECT_EQ(downloadMesh(*viaSecond, "shared", &status, &metadata), mesh);
  EXPECT_EQ(metadata.sha256(), uploaded.mesh.sha256());
  // The id is taken on every replica.
  EXPECT_EQ(uploadMessages(*viaSecond, arraysUpload("shared", mesh)).status.error_code(),
            grpc::StatusCode::ALREADY_EXISTS);
  // A delete through one replica is seen by the other, even though the other cached the mesh.
  grpc::ClientContext context;
  prepare(context);
  v1::DeleteMeshRequest request;
  request.set_name("meshes/shared");
  google::protobuf::Empty empty;
  ASSERT_TRUE(viaSecond->DeleteMesh(&context, request, &empty).ok());
  downloadMesh(*viaFirst, "shared", &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
}

}  // namespace
}  // namespace tessera::test
