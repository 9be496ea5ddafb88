// MeshService against the real server, on each store: what goes in comes back out bit for bit,
// with counts and checksums computed here independently of the server's code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tests/server/store_fixture.h"

namespace tessera::test {
namespace {

using MeshServiceTest = StoreTest;

// Independent expectations for bigguy.obj: MODELS-STATS.csv in the models folder lists 1452
// vertices and 1450 quads.
constexpr int64_t kBigguyVertices = 1452;
constexpr int64_t kBigguyFaces = 1450;

TEST_P(MeshServiceTest, UploadObjReportsTheModelsCountsBoundsAndChecksum) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  std::string text = readFile(modelPath("bigguy.obj"));
  MeshArrays expected = parseObjVerticesAndFaces(text);

  UploadResult result = uploadMessages(*stub, objUpload("bigguy", text, 10'000, "bigguy.obj"));

  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  const v1::Mesh& mesh = result.mesh;
  EXPECT_EQ(mesh.name(), "meshes/bigguy");
  EXPECT_EQ(mesh.display_name(), "bigguy.obj");
  EXPECT_EQ(mesh.source_format(), v1::MESH_FORMAT_OBJ);
  EXPECT_EQ(mesh.source_bytes(), static_cast<int64_t>(text.size()));
  EXPECT_EQ(mesh.vertex_count(), kBigguyVertices);
  EXPECT_EQ(mesh.face_count(), kBigguyFaces);
  EXPECT_EQ(mesh.face_vertex_count(), 4 * kBigguyFaces);
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < expected.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], expected.positions[i]);
    hi[i % 3] = std::max(hi[i % 3], expected.positions[i]);
  }
  EXPECT_EQ(mesh.bounding_box().min().x(), lo[0]);
  EXPECT_EQ(mesh.bounding_box().max().z(), hi[2]);
  EXPECT_EQ(mesh.sha256(), sha256Hex(canonicalEncoding(expected)));
  EXPECT_EQ(mesh.stored_bytes(), static_cast<int64_t>(canonicalEncoding(expected).size()));
  EXPECT_GT(mesh.create_time().seconds(), 1'600'000'000);
}

// bigguy, and OpenSubdiv's catmark_nonman_quadpole8 (non-manifold: faces that repeat a vertex).
TEST_P(MeshServiceTest, ObjAndArraysUploadsOfOneMeshAgreeAndDownloadBitForBit) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  for (const std::string model : {"bigguy", "opensubdiv-shapes/catmark_nonman_quadpole8"}) {
    SCOPED_TRACE(model);
    const std::string id = model == "bigguy" ? "bigguy" : "quadpole";
    std::string text = readFile(modelPath(model + ".obj"));
    MeshArrays arrays = parseObjVerticesAndFaces(text);

    UploadResult fromObj = uploadMessages(*stub, objUpload(id + "-obj", text));
    // 1000 floats per chunk: chunk boundaries fall inside vertices.
    UploadResult fromArrays = uploadMessages(*stub, arraysUpload(id + "-arrays", arrays, 1000));

    ASSERT_TRUE(fromObj.status.ok()) << fromObj.status.error_message();
    ASSERT_TRUE(fromArrays.status.ok()) << fromArrays.status.error_message();
    EXPECT_EQ(fromObj.mesh.sha256(), fromArrays.mesh.sha256());
    EXPECT_EQ(fromArrays.mesh.source_bytes(), arrays.uploadBytes());
    grpc::Status status;
    EXPECT_EQ(downloadMesh(*stub, id + "-obj", &status), arrays);
    EXPECT_TRUE(status.ok()) << status.error_message();
    EXPECT_EQ(downloadMesh(*stub, id + "-arrays", &status), arrays);
  }
}

TEST_P(MeshServiceTest, CreasesCornersAndHolesRoundTrip) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  MeshArrays mesh = gridMesh(4, 1);
  mesh.creases = {{0, 1, 2.5f}, {1, 2, 10.0f}};
  mesh.corners = {{0, 3.0f}};
  mesh.holes = {5};

  UploadResult result = uploadMessages(*stub, arraysUpload("tagged", mesh));

  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  EXPECT_EQ(result.mesh.crease_count(), 2);
  EXPECT_EQ(result.mesh.corner_count(), 1);
  EXPECT_EQ(result.mesh.hole_count(), 1);
  EXPECT_EQ(result.mesh.sha256(), sha256Hex(canonicalEncoding(mesh)));
  grpc::Status status;
  EXPECT_EQ(downloadMesh(*stub, "tagged", &status), mesh);
}

// Rules come from the OBJ's tags unless the header names them; the checksum covers them, packed as
// mesh.proto documents (boundary | Chaikin << 8 | smooth triangles << 16).
// A mesh far from the origin for its size (a grid of unit squares a million units away) is stored
// relative to its box's centre: its box is reported in model units, DownloadMesh sends the origin
// with the relative positions, and an arrays upload of those with the origin is the same mesh.
TEST_P(MeshServiceTest, AMeshFarFromTheOriginKeepsItsDetailRelativeToItsCentre) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  std::string obj;
  for (int j = 0; j <= 4; ++j) {
    for (int i = 0; i <= 4; ++i) obj += fmt::format("v {} {} {}\n", 1e6 + i + 0.001 * j, -2e6 + j, 0.25 * ((i + j) % 2));
  }
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      const int v = j * 5 + i + 1;
      obj += fmt::format("f {} {} {} {}\n", v, v + 1, v + 6, v + 5);
    }
  }
  UploadResult fromObj = uploadMessages(*stub, objUpload("far", obj));
  ASSERT_TRUE(fromObj.status.ok()) << fromObj.status.error_message();
  // Model units: the origin plus the stored float positions (within their rounding, ~1e-7 here).
  EXPECT_NEAR(fromObj.mesh.bounding_box().min().x(), 1e6, 1e-6);
  EXPECT_NEAR(fromObj.mesh.bounding_box().max().x(), 1e6 + 4.004, 1e-6);
  EXPECT_NEAR(fromObj.mesh.bounding_box().min().y(), -2e6, 1e-6);
  grpc::Status status;
  MeshArrays arrays = downloadMesh(*stub, "far", &status);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_DOUBLE_EQ(arrays.origin[0], 1e6 + 2.002);
  EXPECT_DOUBLE_EQ(arrays.origin[1], -2e6 + 2);
  // The millimetre steps survive in the float positions (at 1e6 a float steps by 0.0625).
  EXPECT_NEAR(arrays.positions[3 * 5] - arrays.positions[0], 0.001, 1e-6);
  EXPECT_EQ(fromObj.mesh.sha256(), sha256Hex(canonicalEncoding(arrays)));
  UploadResult fromArrays = uploadMessages(*stub, arraysUpload("far-arrays", arrays));
  ASSERT_TRUE(fromArrays.status.ok()) << fromArrays.status.error_message();
  EXPECT_EQ(fromArrays.mesh.sha256(), fromObj.mesh.sha256());
  EXPECT_EQ(fromArrays.mesh.bounding_box().min().x(), fromObj.mesh.bounding_box().min().x());
}

TEST_P(MeshServiceTest, SubdivisionRulesComeFromTheFileOrTheHeaderAndAreStored) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  const std::string chaikin = readFile(modelPath("opensubdiv-shapes/catmark_chaikin2.obj"));
  UploadResult fromFile = uploadMessages(*stub, objUpload("chaikin", chaikin));
  ASSERT_TRUE(fromFile.status.ok()) << fromFile.status.error_message();
  EXPECT_EQ(fromFile.mesh.options().crease_method(), v1::CREASE_METHOD_CHAIKIN);
  EXPECT_EQ(fromFile.mesh.options().triangle_subdivision(), v1::TRIANGLE_SUBDIVISION_CATMARK);
  EXPECT_EQ(fromFile.mesh.options().boundary_interpolation(), v1::BOUNDARY_INTERPOLATION_EDGE_ONLY);
  // Chaikin creases are Far's business (docs/DECISIONS.md): the mesh tessellates like any other.
  auto tessellation = v1::TessellationService::NewStub(server->channel());
  v1::TessellateRequest tessellate;
  tessellate.set_name("meshes/chaikin");
  tessellate.set_relative(1e-2);
  Streamed chaikinGlb = tessellateOverGrpc(*tessellation, tessellate);
  ASSERT_TRUE(chaikinGlb.status.ok()) << chaikinGlb.status.error_message();
  EXPECT_TRUE(chaikinGlb.problem.empty()) << chaikinGlb.problem;
  ASSERT_TRUE(chaikinGlb.summary);
  EXPECT_GT(chaikinGlb.summary->triangles(), 0);

  std::vector<v1::UploadMeshRequest> uniform = objUpload("chaikin-as-uniform", chaikin);
  uniform[0].mutable_header()->mutable_options()->set_crease_method(v1::CREASE_METHOD_UNIFORM);
  UploadResult overridden = uploadMessages(*stub, uniform);
  ASSERT_TRUE(overridden.status.ok()) << overridden.status.error_message();
  EXPECT_EQ(overridden.mesh.options().crease_method(), v1::CREASE_METHOD_UNIFORM);
  EXPECT_NE(overridden.mesh.sha256(), fromFile.mesh.sha256());

  const MeshArrays mesh = gridMesh(4, 2);  // its inner 2 x 2 faces keep a surface under NONE
  std::vector<v1::UploadMeshRequest> arrays = arraysUpload("all-rules", mesh);
  v1::SubdivisionOptions* options = arrays[0].mutable_header()->mutable_options();
  options->set_boundary_interpolation(v1::BOUNDARY_INTERPOLATION_NONE);
  options->set_crease_method(v1::CREASE_METHOD_CHAIKIN);
  options->set_triangle_subdivision(v1::TRIANGLE_SUBDIVISION_SMOOTH);
  UploadResult all = uploadMessages(*stub, arrays);
  ASSERT_TRUE(all.status.ok()) << all.status.error_message();
  EXPECT_EQ(all.mesh.sha256(), sha256Hex(canonicalEncoding(mesh, 3 | 1 << 8 | 1 << 16)));

  grpc::ClientContext context;
  prepare(context);
  v1::GetMeshRequest request;
  request.set_name("meshes/all-rules");
  v1::Mesh got;
  ASSERT_TRUE(stub->GetMesh(&context, request, &got).ok());
  EXPECT_EQ(got.options().boundary_interpolation(), v1::BOUNDARY_INTERPOLATION_NONE);
  EXPECT_EQ(got.options().crease_method(), v1::CREASE_METHOD_CHAIKIN);
  EXPECT_EQ(got.options().triangle_subdivision(), v1::TRIANGLE_SUBDIVISION_SMOOTH);
}

TEST_P(MeshServiceTest, GetReturnsWhatUploadReturned) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  UploadResult uploaded = uploadMessages(*stub, arraysUpload("grid", gridMesh(3, 7)));
  ASSERT_TRUE(uploaded.status.ok()) << uploaded.status.error_message();

  grpc::ClientContext context;
  prepare(context);
  v1::GetMeshRequest request;
  request.set_name("meshes/grid");
  v1::Mesh got;
  grpc::Status status = stub->GetMesh(&context, request, &got);

  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(got.SerializeAsString(), uploaded.mesh.SerializeAsString());
}

TEST_P(MeshServiceTest, ListPagesThroughEveryMeshInIdOrder) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  std::vector<std::string> ids = {"m-7", "a1", "m-10", "zz", "b", "m-2", "0start"};
  for (size_t i = 0; i < ids.size(); ++i) {
    ASSERT_TRUE(uploadMessages(*stub, arraysUpload(ids[i], gridMesh(2, int(i)))).status.ok());
  }
  std::sort(ids.begin(), ids.end());  // bytewise, as the API promises

  std::vector<std::string> listed;
  std::vector<int> pageSizes;
  v1::ListMeshesRequest request;
  request.set_page_size(3);
  do {
    grpc::ClientContext context;
    prepare(context);
    v1::ListMeshesResponse page;
    grpc::Status status = stub->ListMeshes(&context, request, &page);
    ASSERT_TRUE(status.ok()) << status.error_message();
    pageSizes.push_back(page.meshes_size());
    for (const auto& m : page.meshes()) listed.push_back(m.name().substr(7));
    request.set_page_token(page.next_page_token());
  } while (!request.page_token().empty() && pageSizes.size() < 10);

  EXPECT_EQ(listed, ids);
  EXPECT_EQ(pageSizes, (std::vector<int>{3, 3, 1}));
}

TEST_P(MeshServiceTest, DeleteRemovesTheMeshAndLaterCallsReportNotFound) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  ASSERT_TRUE(uploadMessages(*stub, arraysUpload("doomed", gridMesh(2, 0))).status.ok());
  ASSERT_TRUE(uploadMessages(*stub, arraysUpload("kept", gridMesh(2, 1))).status.ok());

  grpc::ClientContext context;
  prepare(context);
  v1::DeleteMeshRequest request;
  request.set_name("meshes/doomed");
  google::protobuf::Empty empty;
  ASSERT_TRUE(stub->DeleteMesh(&context, request, &empty).ok());

  grpc::ClientContext again;
  prepare(again);
  grpc::Status second = stub->DeleteMesh(&again, request, &empty);
  EXPECT_EQ(second.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_NE(second.error_message().find("meshes/doomed"), std::string::npos);
  grpc::Status downloaded;
  downloadMesh(*stub, "doomed", &downloaded);
  EXPECT_EQ(downloaded.error_code(), grpc::StatusCode::NOT_FOUND);
  downloadMesh(*stub, "kept", &downloaded);
  EXPECT_TRUE(downloaded.ok());
  // The id is free again.
  EXPECT_TRUE(uploadMessages(*stub, arraysUpload("doomed", gridMesh(3, 0))).status.ok());
}

TEST_P(MeshServiceTest, ADuplicateIdIsRefusedAndTheFirstMeshIsKept) {
  auto server = startServer();
  ASSERT_TRUE(server);
  auto stub = v1::MeshService::NewStub(server->channel());
  MeshArrays first = gridMesh(2, 1);
  ASSERT_TRUE(uploadMessages(*stub, arraysUpload("dup", first)).status.ok());

  UploadResult second = uploadMessages(*stub, arraysUpload("dup", gridMesh(3, 2)));

  EXPECT_EQ(second.status.error_code(), grpc::StatusCode::ALREADY_EXISTS);
  EXPECT_NE(second.status.error_message().find("meshes/dup already exists"), std::string::npos);
  grpc::Status status;
  EXPECT_EQ(downloadMesh(*stub, "dup", &status), first);
}

TEST_P(MeshServiceTest, MeshesSurviveAGracefulRestart) {
  auto server = startServer();
  ASSERT_TRUE(server);
  MeshArrays mesh = gridMesh(5, 3);
  {
    auto stub = v1::MeshService::NewStub(server->channel());
    ASSERT_TRUE(uploadMessages(*stub, arraysUpload("persistent", mesh)).status.ok());
  }
  EXPECT_EQ(server->terminate(), 0);

  auto restarted = startServer();
  ASSERT_TRUE(restarted);
  auto stub = v1::MeshService::NewStub(restarted->channel());
  grpc::Status status;
  EXPECT_EQ(downloadMesh(*stub, "persistent", &status), mesh);
  EXPECT_TRUE(status.ok()) << status.error_message();
}

TESSERA_INSTANTIATE_STORE_TESTS(MeshServiceTest);

}  // namespace
}  // namespace tessera::test
