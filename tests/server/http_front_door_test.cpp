// The HTTP front door (server/http/) against the real server: REST/JSON for the mesh calls, the
// GLB streamed with a strong ETag and conditional GET, a frame, statuses mapped from gRPC with
// the same messages, the bearer token, CORS. The reference for every body is the same call over
// gRPC to the same server.
#include <gtest/gtest.h>
#include <httplib.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fmt/format.h>

#include <csignal>
#include <cstring>
#include <string>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

constexpr const char* kOrigin = "https://viewer.example";

class HttpFrontDoor : public ::testing::Test {
 protected:
  // A refused upload's connection may close while the client still writes its body.
  void SetUp() override { std::signal(SIGPIPE, SIG_IGN); }

  void startServer(std::vector<std::string> flags = {}) {
    flags.insert(flags.end(), {"--store", "sqlite:" + (dir_.path() / "h.db").string(), "--http-listen",
                               "127.0.0.1:0", "--http-cors-origin", kOrigin});
    server_ = ServerProcess::start(dir_.path(), flags);
    ASSERT_TRUE(server_);
    ASSERT_FALSE(server_->httpAddress().empty()) << "no http= line in the ready file";
    const std::string& address = server_->httpAddress();
    const size_t colon = address.rfind(':');
    http_ = std::make_unique<httplib::Client>(address.substr(0, colon), std::stoi(address.substr(colon + 1)));
    http_->set_read_timeout(120, 0);
  }

  httplib::Result uploadObj(const std::string& id, const std::string& text, const httplib::Headers& headers = {}) {
    return http_->Post(("/v1/meshes?id=" + id).c_str(), headers, text, "text/plain");
  }

  TempDir dir_;
  std::unique_ptr<ServerProcess> server_;
  std::unique_ptr<httplib::Client> http_;
};

TEST_F(HttpFrontDoor, MeshesAreUploadedListedReadAndDeletedAsJson) {
  startServer();
  const std::string obj = readFile(modelPath("opensubdiv-shapes/catmark_torus_creases0.obj"));
  auto created = uploadObj("torus", obj);
  ASSERT_TRUE(created);
  EXPECT_EQ(created->status, 201) << created->body;
  EXPECT_EQ(created->get_header_value("Location"), "/v1/meshes/torus");
  EXPECT_EQ(created->get_header_value("Content-Type"), "application/json");
  EXPECT_NE(created->body.find("\"name\":\"meshes/torus\""), std::string::npos) << created->body;

  // The same metadata as GetMesh over gRPC says.
  auto stub = v1::MeshService::NewStub(server_->channel());
  grpc::ClientContext context;
  prepare(context);
  v1::GetMeshRequest get;
  get.set_name("meshes/torus");
  v1::Mesh mesh;
  ASSERT_TRUE(stub->GetMesh(&context, get, &mesh).ok());
  auto read = http_->Get("/v1/meshes/torus");
  ASSERT_TRUE(read);
  EXPECT_EQ(read->status, 200);
  EXPECT_NE(read->body.find("\"sha256\":\"" + mesh.sha256() + "\""), std::string::npos) << read->body;
  EXPECT_NE(read->body.find("\"faceCount\":\"" + std::to_string(mesh.face_count()) + "\""), std::string::npos);

  auto list = http_->Get("/v1/meshes?page_size=10");
  ASSERT_TRUE(list);
  EXPECT_EQ(list->status, 200);
  EXPECT_NE(list->body.find("meshes/torus"), std::string::npos);

  auto again = uploadObj("torus", obj);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 409) << again->body;  // ALREADY_EXISTS
  EXPECT_NE(again->body.find("\"code\":\"ALREADY_EXISTS\""), std::string::npos);

  auto removed = http_->Delete("/v1/meshes/torus");
  ASSERT_TRUE(removed);
  EXPECT_EQ(removed->status, 204);
  auto gone = http_->Get("/v1/meshes/torus");
  ASSERT_TRUE(gone);
  EXPECT_EQ(gone->status, 404);
  EXPECT_NE(gone->body.find("\"code\":\"NOT_FOUND\""), std::string::npos) << gone->body;
}

// little-endian float32 bytes, as a positions-only upload's body carries them.
std::string floatBytes(const std::vector<float>& values) {
  std::string bytes;
  for (float value : values) {
    uint32_t bits;
    std::memcpy(&bits, &value, 4);
    for (int b = 0; b < 4; ++b) bytes.push_back(char(bits >> (8 * b) & 0xff));
  }
  return bytes;
}

// A positions-only upload (topology_of): the body's floats are the positions, then uv_values UV
// numbers; the mesh is the one a full upload of the same arrays makes, checksum computed here.
TEST_F(HttpFrontDoor, APositionsOnlyUploadTakesTheTopologyOfAStoredMesh) {
  startServer();
  auto stub = v1::MeshService::NewStub(server_->channel());
  ASSERT_TRUE(uploadModel(*stub, "bigguy").status.ok());
  grpc::Status status;
  MeshArrays edited = downloadMesh(*stub, "bigguy", &status);
  ASSERT_TRUE(status.ok());
  for (size_t i = 1; i < edited.positions.size(); i += 3) edited.positions[i] *= 1.01f;
  for (float& c : edited.uvs) c *= 0.5f;
  edited.origin = {1, 2, 3};
  std::vector<float> body = edited.positions;
  body.insert(body.end(), edited.uvs.begin(), edited.uvs.end());
  auto created = http_->Post(fmt::format("/v1/meshes?id=edit&topology_of=bigguy&uv_values={}&origin=1,2,3",
                                         edited.uvs.size()).c_str(),
                             floatBytes(body), "application/octet-stream");
  ASSERT_TRUE(created);
  EXPECT_EQ(created->status, 201) << created->body;
  EXPECT_EQ(created->get_header_value("Location"), "/v1/meshes/edit");
  EXPECT_NE(created->body.find("\"sha256\":\"" + sha256Hex(canonicalEncoding(edited)) + "\""), std::string::npos)
      << created->body;
  EXPECT_EQ(downloadMesh(*stub, "edit", &status), edited);

  // Without UVs it keeps the stored mesh's; meshes/ID names it too.
  auto kept = http_->Post("/v1/meshes?id=edit2&topology_of=meshes/edit", floatBytes(edited.positions),
                          "application/octet-stream");
  ASSERT_TRUE(kept);
  EXPECT_EQ(kept->status, 201) << kept->body;
  edited.origin = {0, 0, 0};
  EXPECT_EQ(downloadMesh(*stub, "edit2", &status), edited);

  struct Refusal {
    std::string query;
    std::string body;
    int status;
    std::vector<std::string> said;
  };
  const std::vector<float> fewer(edited.positions.begin(), edited.positions.end() - 3);
  const std::vector<Refusal> refusals = {
      {"id=x&topology_of=nope", floatBytes(edited.positions), 404, {"NOT_FOUND", "meshes/nope"}},
      {"id=x&topology_of=bigguy", floatBytes(fewer), 400,
       {"INVALID_ARGUMENT", "arrays.positions", "meshes/bigguy", "4353 floats", "1452 vertices"}},
      {"id=x&topology_of=bigguy&uv_values=2", floatBytes(edited.positions) + floatBytes({0.5f, 0.5f}), 400,
       {"INVALID_ARGUMENT", "arrays.uvs: 2 numbers", "meshes/bigguy"}},
      {"id=x&topology_of=bigguy", floatBytes(edited.positions) + "xy", 400, {"not a whole number of 4-byte floats"}},
      {"id=x&topology_of=bigguy&uv_values=-1", floatBytes(edited.positions), 400, {"uv_values"}},
      {"id=x&topology_of=bigguy&origin=1,2", floatBytes(edited.positions), 400, {"origin"}},
      {"id=x&uv_values=2", floatBytes(edited.positions), 400, {"uv_values"}},  // only with topology_of
  };
  for (const Refusal& r : refusals) {
    SCOPED_TRACE(r.query);
    auto refused = http_->Post(("/v1/meshes?" + r.query).c_str(), r.body, "application/octet-stream");
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, r.status) << refused->body;
    for (const std::string& part : r.said) EXPECT_NE(refused->body.find(part), std::string::npos) << refused->body;
  }
}

TEST_F(HttpFrontDoor, TheGlbIsTheGrpcOneWithAStrongEtagAndConditionalGet) {
  startServer();
  ASSERT_EQ(uploadObj("bigguy", readFile(modelPath("bigguy.obj")))->status, 201);
  const std::string query = "/v1/meshes/bigguy/tessellation.glb?relative=1e-3&encoding=meshopt";
  auto glb = http_->Get(query.c_str());
  ASSERT_TRUE(glb);
  ASSERT_EQ(glb->status, 200) << glb->body;
  EXPECT_EQ(glb->get_header_value("Content-Type"), "model/gltf-binary");
  const std::string tag = glb->get_header_value("ETag");
  ASSERT_GT(tag.size(), 2u);
  EXPECT_EQ(tag.front(), '"') << "a strong ETag is quoted, without W/";

  auto stub = v1::TessellationService::NewStub(server_->channel());
  v1::TessellateRequest request;
  request.set_name("meshes/bigguy");
  request.set_relative(1e-3);
  request.set_encoding(v1::GLB_ENCODING_MESHOPT);
  const Streamed reference = tessellateOverGrpc(*stub, request);
  ASSERT_TRUE(reference.status.ok()) << reference.status.error_message();
  EXPECT_EQ(glb->body, reference.glb) << "the front door streams exactly the GLB gRPC does";

  auto cached = http_->Get(query.c_str(), {{"If-None-Match", tag}, {"X-Request-Id", "conditional-7"}});
  ASSERT_TRUE(cached);
  EXPECT_EQ(cached->status, 304);
  EXPECT_TRUE(cached->body.empty());
  EXPECT_EQ(cached->get_header_value("ETag"), tag);
  // A 304 is an answer like any other: the client's id comes back, or the one the server made.
  EXPECT_EQ(cached->get_header_value("X-Request-Id"), "conditional-7");
  auto unnamed = http_->Get(query.c_str(), {{"If-None-Match", tag}});
  ASSERT_TRUE(unnamed);
  EXPECT_EQ(unnamed->status, 304);
  EXPECT_FALSE(unnamed->get_header_value("X-Request-Id").empty()) << "the server's own request id";

  // Another request, another tag; the same request again, the same tag.
  auto coarser = http_->Get("/v1/meshes/bigguy/tessellation.glb?relative=1e-2&encoding=meshopt",
                            {{"If-None-Match", tag}});
  ASSERT_TRUE(coarser);
  EXPECT_EQ(coarser->status, 200);
  EXPECT_NE(coarser->get_header_value("ETag"), tag);
  EXPECT_EQ(http_->Get(query.c_str())->get_header_value("ETag"), tag);
}

TEST_F(HttpFrontDoor, RefusalsAreHttpStatusesWithTheApisMessages) {
  startServer();
  ASSERT_EQ(uploadObj("torus", readFile(modelPath("opensubdiv-shapes/catmark_torus_creases0.obj")))->status, 201);
  struct Case {
    std::string path;
    int status;
    std::string code, words;
  };
  const std::vector<Case> cases = {
      {"/v1/meshes/torus/tessellation.glb?relative=0", 400, "INVALID_ARGUMENT", "relative: must be positive"},
      {"/v1/meshes/torus/tessellation.glb?relative=abc", 400, "INVALID_ARGUMENT", "relative: expects a number"},
      {"/v1/meshes/torus/tessellation.glb?relativ=1e-3", 400, "INVALID_ARGUMENT", "relativ"},
      {"/v1/meshes/torus/tessellation.glb?relative=1e-3&relative=1e-2", 400, "INVALID_ARGUMENT", "more than once"},
      // Finer than the server ever serves: a 400, not a 429 that invites a retry.
      {"/v1/meshes/torus/tessellation.glb?relative=1e-12", 400, "INVALID_ARGUMENT", "min_relative_tolerance"},
      {"/v1/meshes/torus/tessellation.glb?eye=0,0,5&target=0,0,0&fov=1e-3", 400, "INVALID_ARGUMENT",
       "finer than the server's minimum 1e-06 (min_relative_tolerance)"},
      {"/v1/meshes/torus/frame.png?eye=0,0,5&target=0,0,0&fov=1e-3", 400, "INVALID_ARGUMENT",
       "cameras[0]: pixel accuracy 0.5 px at this camera asks"},
      {"/v1/meshes/torus/tessellation.glb?eye=0,0,5&target=0,0,5", 400, "INVALID_ARGUMENT",
       "eye and target must be distinct"},
      {"/v1/meshes/torus/tessellation.glb?eye=0,0,5", 400, "INVALID_ARGUMENT", "target: is required"},
      {"/v1/meshes/ghost/tessellation.glb?relative=1e-3", 404, "NOT_FOUND", "ghost"},
      {"/v1/meshes/torus/tessellation.glb?relative=1e-3&timeout_ms=-4", 400, "INVALID_ARGUMENT", "timeout_ms"},
      {"/v1/meshes/torus/frame.png?target=0,0,0", 400, "INVALID_ARGUMENT", "eye: is required"},
      {"/v1/elsewhere", 404, "NOT_FOUND", "no such endpoint"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.path);
    auto response = http_->Get(c.path.c_str());
    ASSERT_TRUE(response);
    EXPECT_EQ(response->status, c.status) << response->body;
    EXPECT_EQ(response->get_header_value("Content-Type"), "application/json");
    EXPECT_NE(response->body.find("\"code\":\"" + c.code + "\""), std::string::npos) << response->body;
    EXPECT_NE(response->body.find(c.words), std::string::npos) << response->body;
  }
  auto noLength = http_->Post("/v1/meshes?id=x", httplib::Headers{}, [](size_t, httplib::DataSink& sink) {
    sink.write("v 0 0 0\n", 8);
    sink.done();
    return true;
  }, "text/plain");
  ASSERT_TRUE(noLength);
  EXPECT_EQ(noLength->status, 411);
  auto badObj = uploadObj("broken", "v 0 0 0\nf 1 2 3\n");
  ASSERT_TRUE(badObj);
  EXPECT_EQ(badObj->status, 400) << badObj->body;
  EXPECT_NE(badObj->body.find("INVALID_ARGUMENT"), std::string::npos);
}

TEST_F(HttpFrontDoor, TheTokenIsTheSameAsForGrpcAndCorsIsAnswered) {
  startServer({"--token", "s3cret"});
  const std::string obj = readFile(modelPath("opensubdiv-shapes/catmark_torus_creases0.obj"));
  auto refused = uploadObj("torus", obj);
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 401);
  EXPECT_EQ(refused->get_header_value("WWW-Authenticate"), "Bearer");
  EXPECT_EQ(uploadObj("torus", obj, {{"Authorization", "Bearer wrong"}})->status, 401);
  auto accepted = uploadObj("torus", obj, {{"Authorization", "Bearer s3cret"}});
  ASSERT_TRUE(accepted);
  EXPECT_EQ(accepted->status, 201) << accepted->body;
  EXPECT_EQ(accepted->get_header_value("Access-Control-Allow-Origin"), kOrigin);

  auto preflight = http_->Options("/v1/meshes/torus/tessellation.glb", {{"Origin", kOrigin},
                                                                         {"Access-Control-Request-Method", "GET"}});
  ASSERT_TRUE(preflight);
  EXPECT_EQ(preflight->status, 204);
  EXPECT_EQ(preflight->get_header_value("Access-Control-Allow-Origin"), kOrigin);
  EXPECT_NE(preflight->get_header_value("Access-Control-Allow-Headers").find("Authorization"), std::string::npos);
  auto glb = http_->Get("/v1/meshes/torus/tessellation.glb?relative=1e-2", {{"Authorization", "Bearer s3cret"}});
  ASSERT_TRUE(glb);
  EXPECT_EQ(glb->status, 200);
  EXPECT_NE(glb->get_header_value("Access-Control-Expose-Headers").find("ETag"), std::string::npos);
}

TEST_F(HttpFrontDoor, AnUploadOverTheServersLimitIsRefusedWithItsMessage) {
  startServer({"--max-upload-bytes", "100000"});
  const std::string obj = readFile(modelPath("bigguy.obj"));
  ASSERT_GT(obj.size(), 150000u);
  auto refused = uploadObj("bigguy", obj);
  ASSERT_TRUE(refused) << "the refusal must reach the client, not a reset connection";
  EXPECT_EQ(refused->status, 429) << refused->body;
  EXPECT_NE(refused->body.find("max_upload_bytes"), std::string::npos) << refused->body;
  EXPECT_EQ(http_->Get("/v1/meshes/bigguy")->status, 404);
}

// A client that reads a little of a large GLB and hangs up costs the server that response only.
TEST_F(HttpFrontDoor, AClientThatHangsUpMidGlbLeavesTheServerServing) {
  startServer();
  ASSERT_EQ(uploadObj("bigguy", readFile(modelPath("bigguy.obj")))->status, 201);
  const std::string& address = server_->httpAddress();
  const size_t colon = address.rfind(':');
  for (int attempt = 0; attempt < 3; ++attempt) {
    addrinfo hints{};
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    ASSERT_EQ(getaddrinfo(address.substr(0, colon).c_str(), address.substr(colon + 1).c_str(), &hints, &found), 0);
    const int fd = socket(found->ai_family, SOCK_STREAM, 0);
    ASSERT_EQ(connect(fd, found->ai_addr, found->ai_addrlen), 0);
    freeaddrinfo(found);
    const std::string request =
        "GET /v1/meshes/bigguy/tessellation.glb?relative=2e-4 HTTP/1.1\r\nHost: test\r\n\r\n";
    ASSERT_EQ(send(fd, request.data(), request.size(), MSG_NOSIGNAL), ssize_t(request.size()));
    char some[512];
    EXPECT_GT(recv(fd, some, sizeof some, 0), 0);
    close(fd);
  }
  auto list = http_->Get("/v1/meshes");
  ASSERT_TRUE(list) << "the server went away";
  EXPECT_EQ(list->status, 200);
  auto glb = http_->Get("/v1/meshes/bigguy/tessellation.glb?relative=1e-2");
  ASSERT_TRUE(glb);
  EXPECT_EQ(glb->status, 200);
}

TEST_F(HttpFrontDoor, AFrameIsAnImageOfTheRequestedSize) {
  startServer();
  ASSERT_EQ(uploadObj("torus", readFile(modelPath("opensubdiv-shapes/catmark_torus_creases0.obj")))->status, 201);
  auto frame = http_->Get("/v1/meshes/torus/frame.png?eye=0,2,4&target=0,0,0&size=160x120");
  ASSERT_TRUE(frame);
  if (frame->status == 501) GTEST_SKIP() << "this server renders nothing: " << frame->body;
  ASSERT_EQ(frame->status, 200) << frame->body;
  EXPECT_EQ(frame->get_header_value("Content-Type"), "image/png");
  ASSERT_GT(frame->body.size(), 24u);
  EXPECT_EQ(frame->body.substr(1, 3), "PNG");
  // IHDR: width and height, big-endian, at bytes 16 and 20.
  auto be32 = [&](size_t at) {
    return (uint32_t(uint8_t(frame->body[at])) << 24) | (uint32_t(uint8_t(frame->body[at + 1])) << 16) |
           (uint32_t(uint8_t(frame->body[at + 2])) << 8) | uint32_t(uint8_t(frame->body[at + 3]));
  };
  EXPECT_EQ(be32(16), 160u);
  EXPECT_EQ(be32(20), 120u);
}

}  // namespace
}  // namespace tessera::test
