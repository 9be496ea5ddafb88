// gRPC reflection v1 (server/app/reflection_v1.h) on the real server, against the server's API as the
// generated code defines it: the services it offers, files with their dependencies, errors for
// what does not exist, and nothing at all once a bearer token is set.
#include <google/protobuf/descriptor.pb.h>
#include <gtest/gtest.h>

#include <set>

#include "grpc/reflection/v1/reflection.grpc.pb.h"
#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

namespace reflection = grpc::reflection::v1;
using Stream = grpc::ClientReaderWriter<reflection::ServerReflectionRequest,
                                        reflection::ServerReflectionResponse>;

// One ServerReflectionInfo stream to `server`.
struct ReflectionCall {
  explicit ReflectionCall(const ServerProcess& server)
      : stub(reflection::ServerReflection::NewStub(server.channel())) {
    prepare(context);
    stream = stub->ServerReflectionInfo(&context);
  }
  std::unique_ptr<reflection::ServerReflection::Stub> stub;
  grpc::ClientContext context;
  std::unique_ptr<Stream> stream;
};

reflection::ServerReflectionRequest listServices() {
  reflection::ServerReflectionRequest list;
  list.set_list_services("");
  return list;
}

reflection::ServerReflectionResponse ask(Stream& stream,
                                         const reflection::ServerReflectionRequest& request) {
  reflection::ServerReflectionResponse response;
  EXPECT_TRUE(stream.Write(request));
  EXPECT_TRUE(stream.Read(&response));
  return response;
}

TEST(Reflection, V1ListsTheServicesAndServesFilesWithTheirDependencies) {
  TempDir dir;
  auto server =
      ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string()});
  ASSERT_TRUE(server);
  ReflectionCall call(*server);
  Stream* stream = call.stream.get();
  const reflection::ServerReflectionResponse listed = ask(*stream, listServices());
  std::set<std::string> names;
  for (const auto& service : listed.list_services_response().service())
    names.insert(service.name());
  EXPECT_EQ(names, (std::set<std::string>{
                       "grpc.health.v1.Health", "grpc.reflection.v1.ServerReflection",
                       "grpc.reflection.v1alpha.ServerReflection", "tessera.v1.MeshService",
                       "tessera.v1.RenderService", "tessera.v1.ServerInfoService",
                       "tessera.v1.TessellationService"}));

  reflection::ServerReflectionRequest symbol;
  symbol.set_file_containing_symbol("tessera.v1.TessellationService.Tessellate");
  const reflection::ServerReflectionResponse file = ask(*stream, symbol);
  ASSERT_GT(file.file_descriptor_response().file_descriptor_proto_size(), 0) << file.DebugString();
  EXPECT_EQ(file.original_request().file_containing_symbol(), symbol.file_containing_symbol());
  std::set<std::string> sent, needed;
  for (const std::string& bytes : file.file_descriptor_response().file_descriptor_proto()) {
    google::protobuf::FileDescriptorProto proto;
    ASSERT_TRUE(proto.ParseFromString(bytes));
    sent.insert(proto.name());
    needed.insert(proto.dependency().begin(), proto.dependency().end());
  }
  google::protobuf::FileDescriptorProto first;
  ASSERT_TRUE(first.ParseFromString(file.file_descriptor_response().file_descriptor_proto(0)));
  EXPECT_EQ(first.name(), "tessera/v1/tessellation.proto");
  ASSERT_EQ(first.package(), "tessera.v1");
  bool tessellate = false;
  for (const auto& service : first.service()) {
    for (const auto& method : service.method())
      tessellate |= service.name() == "TessellationService" && method.name() == "Tessellate";
  }
  EXPECT_TRUE(tessellate);
  // The first answer on a stream carries every file its files import, so a client can build them.
  for (const std::string& dependency : needed) EXPECT_TRUE(sent.count(dependency)) << dependency;

  reflection::ServerReflectionRequest missing;
  missing.set_file_containing_symbol("tessera.v1.NoSuchService");
  EXPECT_EQ(ask(*stream, missing).error_response().error_code(), int(grpc::StatusCode::NOT_FOUND));
  reflection::ServerReflectionRequest byName;
  byName.set_file_by_filename("tessera/v1/no_such.proto");
  EXPECT_EQ(ask(*stream, byName).error_response().error_code(), int(grpc::StatusCode::NOT_FOUND));
  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());
}

// Reflection cannot be put behind the bearer token, so a server with one offers neither version.
TEST(Reflection, V1IsOffWithAToken) {
  TempDir dir;
  auto server =
      ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string(),
                                        "--token", "secret-token-of-32-characters!!"});
  ASSERT_TRUE(server);
  ReflectionCall call(*server);
  Stream* stream = call.stream.get();
  stream->Write(listServices());
  stream->WritesDone();
  reflection::ServerReflectionResponse response;
  EXPECT_FALSE(stream->Read(&response));
  EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::UNIMPLEMENTED);
}

}  // namespace
}  // namespace tessera::test
