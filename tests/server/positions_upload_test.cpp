// Positions-only uploads (UploadMeshHeader.topology_of) against the real server, on each store: the
// new mesh is the mesh a full upload of the same arrays makes (the checksum computed here from the
// documented encoding, the arrays downloaded, the GLB of another server that got the full upload),
// it survives a restart and its parent's deletion, the counts are checked, every refusal names
// the problem, and the edited mesh's first tessellation reuses the kept topology.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "tests/server/store_fixture.h"

namespace tessera::test {
namespace {

using PositionsUploadTest = StoreTest;

// The messages of a positions-only upload: the header naming the topology's mesh, then the
// positions in chunks that end inside vertices, then the UVs (if any) and the origin (if set).
std::vector<v1::UploadMeshRequest> positionsUpload(
    const std::string& id, const std::string& topologyOf, const std::vector<float>& positions,
    const std::vector<float>& uvs = {}, const std::array<double, 3>& origin = {0, 0, 0}) {
  const bool hasOrigin = origin[0] != 0 || origin[1] != 0 || origin[2] != 0;
  const int64_t bytes = 4 * int64_t(positions.size() + uvs.size()) + (hasOrigin ? 24 : 0);
  std::vector<v1::UploadMeshRequest> messages{headerMessage(id, v1::MESH_FORMAT_ARRAYS, bytes)};
  messages[0].mutable_header()->set_topology_of(topologyOf);
  for (size_t begin = 0; begin < positions.size(); begin += 1000) {
    v1::UploadMeshRequest chunk;
    for (size_t i = begin; i < std::min(begin + 1000, positions.size()); ++i)
      chunk.mutable_arrays()->add_positions(positions[i]);
    messages.push_back(chunk);
  }
  v1::UploadMeshRequest rest;
  for (float c : uvs) rest.mutable_arrays()->add_uvs(c);
  if (hasOrigin) {
    rest.mutable_arrays()->mutable_origin()->set_x(origin[0]);
    rest.mutable_arrays()->mutable_origin()->set_y(origin[1]);
    rest.mutable_arrays()->mutable_origin()->set_z(origin[2]);
  }
  if (!uvs.empty() || hasOrigin) messages.push_back(rest);
  return messages;
}

// bigguy (with its UVs) as the server stored it, its vertices moved smoothly: an edited cage.
MeshArrays editedCage(const MeshArrays& cage, float amount) {
  MeshArrays edited = cage;
  for (size_t v = 0; v < edited.vertexCount(); ++v) {
    float* p = &edited.positions[3 * v];
    p[1] += amount * std::sin(p[0]) * std::cos(p[2]);
  }
  return edited;
}

v1::TessellateRequest requestAt(const std::string& id, double relative) {
  v1::TessellateRequest request;
  request.set_name("meshes/" + id);
  request.set_relative(relative);
  return request;
}

double metric(const ServerProcess& server, const std::string& series) {
  return seriesValue(httpGet(server.metricsAddress(), "/metrics"), series);
}

class WithBigguy : public PositionsUploadTest {
 protected:
  void SetUp() override {
    PositionsUploadTest::SetUp();
    if (IsSkipped()) return;
    server_ = startServer();
    ASSERT_TRUE(server_);
    stub_ = v1::MeshService::NewStub(server_->channel());
    UploadResult parent = uploadModel(*stub_, "bigguy");
    ASSERT_TRUE(parent.status.ok()) << parent.status.error_message();
    grpc::Status status;
    cage_ = downloadMesh(*stub_, "bigguy", &status);
    ASSERT_TRUE(status.ok()) << status.error_message();
    ASSERT_FALSE(cage_.uvs.empty());  // the UV cases below need them
  }

  UploadResult upload(const std::vector<v1::UploadMeshRequest>& messages) {
    return uploadMessages(*stub_, messages);
  }

  std::unique_ptr<ServerProcess> server_;
  std::unique_ptr<v1::MeshService::Stub> stub_;
  MeshArrays cage_;
};

TEST_P(WithBigguy, APositionsOnlyUploadIsTheMeshAFullUploadMakes) {
  const MeshArrays edited = editedCage(cage_, 0.05f);
  UploadResult result = upload(positionsUpload("bigguy-edit", "meshes/bigguy", edited.positions));
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  EXPECT_EQ(result.mesh.name(), "meshes/bigguy-edit");
  EXPECT_EQ(result.mesh.source_format(), v1::MESH_FORMAT_ARRAYS);
  EXPECT_EQ(result.mesh.source_bytes(), int64_t(4 * edited.positions.size()));
  EXPECT_EQ(result.mesh.vertex_count(), int64_t(edited.vertexCount()));
  EXPECT_EQ(result.mesh.face_count(), int64_t(cage_.faceSizes.size()));
  // The checksum of the documented encoding of the edited arrays, computed here.
  EXPECT_EQ(result.mesh.sha256(), sha256Hex(canonicalEncoding(edited)));
  UploadResult full = upload(arraysUpload("bigguy-full", edited));
  ASSERT_TRUE(full.status.ok()) << full.status.error_message();
  EXPECT_EQ(full.mesh.sha256(), result.mesh.sha256());
  EXPECT_EQ(full.mesh.stored_bytes(), result.mesh.stored_bytes());
  EXPECT_NE(result.mesh.sha256(), sha256Hex(canonicalEncoding(cage_)));

  // Stored on its own: after the parent is deleted and the server restarted it reads back whole.
  grpc::ClientContext context;
  prepare(context);
  google::protobuf::Empty empty;
  v1::DeleteMeshRequest remove;
  remove.set_name("meshes/bigguy");
  ASSERT_TRUE(stub_->DeleteMesh(&context, remove, &empty).ok());
  ASSERT_EQ(server_->terminate(), 0);
  server_ = startServer();
  ASSERT_TRUE(server_);
  stub_ = v1::MeshService::NewStub(server_->channel());
  grpc::Status status;
  v1::Mesh stored;
  EXPECT_EQ(downloadMesh(*stub_, "bigguy-edit", &status, &stored), edited);
  EXPECT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(stored.sha256(), result.mesh.sha256());
}

// The GLB of the positions-only mesh (preprocessed through the topology the upload kept) is the
// GLB another server makes of the full upload of the same cage under the same id, from scratch.
TEST_P(WithBigguy, ItsGlbIsTheFullUploadsBitForBit) {
  const MeshArrays edited = editedCage(cage_, 0.08f);
  ASSERT_TRUE(upload(positionsUpload("edit", "meshes/bigguy", edited.positions)).status.ok());
  auto tessellation = v1::TessellationService::NewStub(server_->channel());
  Streamed fromPositions = tessellateOverGrpc(*tessellation, requestAt("edit", 1e-3));
  ASSERT_TRUE(fromPositions.status.ok()) << fromPositions.status.error_message();
  ASSERT_EQ(fromPositions.problem, "");

  TempDir other;
  auto fullServer =
      ServerProcess::start(other.path(), {"--store", "sqlite:" + (other.path() / "m.db").string()});
  ASSERT_TRUE(fullServer);
  auto fullStub = v1::MeshService::NewStub(fullServer->channel());
  ASSERT_TRUE(uploadMessages(*fullStub, arraysUpload("edit", edited)).status.ok());
  auto fullTessellation = v1::TessellationService::NewStub(fullServer->channel());
  Streamed fromFull = tessellateOverGrpc(*fullTessellation, requestAt("edit", 1e-3));
  ASSERT_TRUE(fromFull.status.ok()) << fromFull.status.error_message();
  EXPECT_GT(fromFull.glb.size(), 1000u);
  EXPECT_TRUE(fromFull.glb == fromPositions.glb)
      << fromFull.glb.size() << " vs " << fromPositions.glb.size() << " bytes";
  // The other server preprocessed from scratch; this one through the kept topology.
  EXPECT_EQ(metric(*fullServer, "tessera_topology_cache_hits_total"), 0);
  EXPECT_EQ(metric(*server_, "tessera_topology_cache_hits_total"), 1);
}

// UVs: none sent keeps the parent's; new ones (all of them) replace them; an origin is the
// upload's own, as in any ARRAYS upload.
TEST_P(WithBigguy, UvsAreKeptUnlessSentAndTheOriginIsTheUploads) {
  MeshArrays edited = editedCage(cage_, 0.02f);
  for (float& c : edited.uvs) c = 0.5f * c + 0.25f;
  edited.origin = {100.0, -20.0, 3.5};
  UploadResult result = upload(
      positionsUpload("newuvs", "meshes/bigguy", edited.positions, edited.uvs, edited.origin));
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  EXPECT_EQ(result.mesh.sha256(), sha256Hex(canonicalEncoding(edited)));
  grpc::Status status;
  EXPECT_EQ(downloadMesh(*stub_, "newuvs", &status), edited);

  // From the new mesh, whose UVs it keeps: a chain of edits.
  MeshArrays again = editedCage(edited, 0.01f);
  again.origin = {0, 0, 0};
  result = upload(positionsUpload("again", "meshes/newuvs", again.positions));
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  EXPECT_EQ(result.mesh.sha256(), sha256Hex(canonicalEncoding(again)));
  EXPECT_EQ(downloadMesh(*stub_, "again", &status), again);
}

// Every refusal names the problem: the mesh named, the counts sent and expected.
TEST_P(WithBigguy, MismatchesAndMissingMeshesAreRefusedNamingTheProblem) {
  const std::vector<float>& positions = cage_.positions;
  const size_t floats = positions.size();
  struct Case {
    const char* what;
    std::vector<v1::UploadMeshRequest> messages;
    grpc::StatusCode code;
    std::vector<std::string> said;
  };
  std::vector<float> fewer(positions.begin(), positions.end() - 3);
  std::vector<float> more = positions;
  more.insert(more.end(), {1, 2, 3});
  std::vector<float> uvsShort(cage_.uvs.begin(), cage_.uvs.end() - 2);
  std::vector<Case> cases = {
      {"no such mesh",
       positionsUpload("x", "meshes/nope", positions),
       grpc::StatusCode::NOT_FOUND,
       {"header.topology_of", "meshes/nope", "not found"}},
      {"a vertex too few",
       positionsUpload("x", "meshes/bigguy", fewer),
       grpc::StatusCode::INVALID_ARGUMENT,
       {"arrays.positions", fmt::format("{} floats", floats - 3), "meshes/bigguy",
        fmt::format("{} vertices", floats / 3), fmt::format("{} floats are needed", floats)}},
      {"a vertex too many",
       positionsUpload("x", "meshes/bigguy", more),
       grpc::StatusCode::INVALID_ARGUMENT,
       {"arrays.positions", fmt::format("{} floats", floats + 3), "meshes/bigguy"}},
      {"no positions",
       positionsUpload("x", "meshes/bigguy", {}, cage_.uvs),
       grpc::StatusCode::INVALID_ARGUMENT,
       {"arrays.positions", "0 floats", "meshes/bigguy"}},
      {"a UV too few",
       positionsUpload("x", "meshes/bigguy", positions, uvsShort),
       grpc::StatusCode::INVALID_ARGUMENT,
       {"arrays.uvs", fmt::format("{} numbers", uvsShort.size()), "meshes/bigguy",
        fmt::format("{} UV numbers", cage_.uvs.size())}},
      {"a malformed name",
       positionsUpload("x", "bigguy", positions),
       grpc::StatusCode::INVALID_ARGUMENT,
       {"header.topology_of"}},
  };
  {
    auto messages = positionsUpload("x", "meshes/bigguy", positions);
    messages.back().mutable_arrays()->add_face_sizes(4);
    messages[0].mutable_header()->set_total_bytes(messages[0].header().total_bytes() + 4);
    cases.push_back({"a topology array",
                     messages,
                     grpc::StatusCode::INVALID_ARGUMENT,
                     {"arrays.face_sizes", "meshes/bigguy", "positions-only"}});
  }
  {
    auto messages = objUpload("x", readFile(modelPath("bigguy.obj")));
    messages[0].mutable_header()->set_topology_of("meshes/bigguy");
    cases.push_back({"an OBJ",
                     messages,
                     grpc::StatusCode::INVALID_ARGUMENT,
                     {"header.format", "MESH_FORMAT_ARRAYS"}});
  }
  {
    auto messages = positionsUpload("x", "meshes/bigguy", positions);
    messages[0].mutable_header()->mutable_options()->set_crease_method(v1::CREASE_METHOD_CHAIKIN);
    cases.push_back({"other rules",
                     messages,
                     grpc::StatusCode::INVALID_ARGUMENT,
                     {"header.options", "meshes/bigguy"}});
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    UploadResult result = upload(c.messages);
    EXPECT_EQ(result.status.error_code(), c.code) << result.status.error_message();
    for (const std::string& part : c.said)
      EXPECT_NE(result.status.error_message().find(part), std::string::npos)
          << "'" << part << "' not in: " << result.status.error_message();
  }
  // None of them stored anything; the same rules, given, are no mismatch.
  grpc::Status status;
  downloadMesh(*stub_, "x", &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  auto same = positionsUpload("x", "meshes/bigguy", positions);
  same[0].mutable_header()->mutable_options()->set_crease_method(v1::CREASE_METHOD_UNIFORM);
  EXPECT_TRUE(upload(same).status.ok());
}

// A mesh without UVs refuses UVs.
TEST_P(PositionsUploadTest, UvsForAMeshWithoutAreRefused) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  MeshArrays grid = gridMesh(3, 1);
  ASSERT_TRUE(uploadMessages(*stub, arraysUpload("grid", grid)).status.ok());
  UploadResult result =
      uploadMessages(*stub, positionsUpload("g2", "meshes/grid", grid.positions, {0.5f, 0.5f}));
  EXPECT_EQ(result.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(result.status.error_message().find(
                "arrays.uvs: 2 numbers, where meshes/grid (header.topology_of) has no UVs"),
            std::string::npos)
      << result.status.error_message();
}

// An edit loop: the parent tessellated once (a one-off keeps no topology), then a positions-only
// upload of an edit: its first tessellation reuses the topology the upload kept, and so do the
// next edits'. A full upload of an edit, for comparison, builds the topology at its tessellation.
TEST_P(WithBigguy, TheEditsFirstTessellationReusesTheTopology) {
  auto tessellation = v1::TessellationService::NewStub(server_->channel());
  ASSERT_TRUE(tessellateOverGrpc(*tessellation, requestAt("bigguy", 1e-2)).status.ok());
  EXPECT_EQ(metric(*server_, "tessera_topology_cache_misses_total"), 1);
  EXPECT_EQ(metric(*server_, "tessera_topology_cache_hits_total"), 0);

  ASSERT_TRUE(upload(positionsUpload("edit1", "meshes/bigguy", editedCage(cage_, 0.03f).positions))
                  .status.ok());
  EXPECT_EQ(metric(*server_, "tessera_topology_cache_misses_total"), 2);  // built by the upload
  ASSERT_TRUE(tessellateOverGrpc(*tessellation, requestAt("edit1", 1e-2)).status.ok());
  EXPECT_EQ(metric(*server_, "tessera_topology_cache_hits_total"), 1);
  EXPECT_EQ(metric(*server_, "tessera_topology_cache_misses_total"), 2);

  // The next edit's upload finds the topology kept (and takes the light lane); its tessellation
  // reuses it.
  ASSERT_TRUE(upload(positionsUpload("edit2", "meshes/edit1", editedCage(cage_, 0.04f).positions))
                  .status.ok());
  ASSERT_TRUE(tessellateOverGrpc(*tessellation, requestAt("edit2", 1e-2)).status.ok());
  EXPECT_EQ(metric(*server_, "tessera_topology_cache_hits_total"), 2);
  EXPECT_EQ(metric(*server_, "tessera_topology_cache_misses_total"), 2);
}

TEST_P(PositionsUploadTest, AFullUploadOfAnEditBuildsTheTopologyAtItsFirstTessellation) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  ASSERT_TRUE(uploadModel(*stub, "bigguy").status.ok());
  grpc::Status status;
  const MeshArrays cage = downloadMesh(*stub, "bigguy", &status);
  auto tessellation = v1::TessellationService::NewStub(server->channel());
  ASSERT_TRUE(tessellateOverGrpc(*tessellation, requestAt("bigguy", 1e-2)).status.ok());
  ASSERT_TRUE(uploadMessages(*stub, arraysUpload("edit1", editedCage(cage, 0.03f))).status.ok());
  ASSERT_TRUE(tessellateOverGrpc(*tessellation, requestAt("edit1", 1e-2)).status.ok());
  EXPECT_EQ(metric(*server, "tessera_topology_cache_hits_total"), 0);
  EXPECT_EQ(metric(*server, "tessera_topology_cache_misses_total"), 2);
}

TESSERA_INSTANTIATE_STORE_TESTS(PositionsUploadTest);
TESSERA_INSTANTIATE_STORE_TESTS(WithBigguy);

}  // namespace
}  // namespace tessera::test
