// The bad-input catalogue: one server, a long list of malformed, unknown, unauthorised and
// over-budget calls, each of which must fail with the right status code and a message naming the
// problem; afterwards the server must still serve a fresh client correctly.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <thread>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

constexpr const char* kToken = "catalogue-secret";
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Case {
  std::string what;
  grpc::StatusCode code;
  std::string messagePart;
  std::function<grpc::Status()> call;
};

class BadInputCatalogue : public ::testing::Test {
 protected:
  void SetUp() override {
    server_ =
        ServerProcess::start(dir_.path(), {"--store", "sqlite:" + (dir_.path() / "m.db").string(),
                                           "--token", kToken, "--max-upload-bytes", "2MiB",
                                           "--max-faces", "2000", "--max-triangles", "1000000"});
    ASSERT_TRUE(server_);
    meshes_ = v1::MeshService::NewStub(server_->channel());
    tessellation_ = v1::TessellationService::NewStub(server_->channel());
    info_ = v1::ServerInfoService::NewStub(server_->channel());
    UploadResult target = upload(arraysUpload("target", gridMesh(4, 0)));
    ASSERT_TRUE(target.status.ok()) << target.status.error_message();
    grpc::ClientContext context;
    prepare(context, kToken);
    v1::ServerInfo info;
    ASSERT_TRUE(info_->GetServerInfo(&context, {}, &info).ok());
    tessellationAvailable_ = info.tessellation_available();
  }

  // What a valid request gets: a result where the build can tessellate, UNIMPLEMENTED otherwise.
  grpc::StatusCode validCode() const {
    return tessellationAvailable_ ? grpc::StatusCode::OK : grpc::StatusCode::UNIMPLEMENTED;
  }
  std::string validMessage() const {
    return tessellationAvailable_ ? "" : "tessellation is not available in this build yet";
  }

  UploadResult upload(const std::vector<v1::UploadMeshRequest>& messages,
                      const std::string& token = kToken) {
    return uploadMessages(*meshes_, messages, token);
  }
  grpc::Status uploadStatus(const std::vector<v1::UploadMeshRequest>& messages) {
    return upload(messages).status;
  }
  std::vector<v1::UploadMeshRequest> arraysWith(const MeshArrays& mesh) {
    return arraysUpload("bad-mesh", mesh);
  }
  std::vector<v1::UploadMeshRequest> withHeader(
      std::vector<v1::UploadMeshRequest> messages,
      const std::function<void(v1::UploadMeshHeader&)>& edit) {
    edit(*messages.front().mutable_header());
    return messages;
  }

  grpc::Status get(const std::string& name) {
    grpc::ClientContext context;
    prepare(context, kToken);
    v1::GetMeshRequest request;
    request.set_name(name);
    v1::Mesh mesh;
    return meshes_->GetMesh(&context, request, &mesh);
  }
  grpc::Status remove(const std::string& name) {
    grpc::ClientContext context;
    prepare(context, kToken);
    v1::DeleteMeshRequest request;
    request.set_name(name);
    google::protobuf::Empty empty;
    return meshes_->DeleteMesh(&context, request, &empty);
  }
  grpc::Status list(int pageSize, const std::string& token) {
    grpc::ClientContext context;
    prepare(context, kToken);
    v1::ListMeshesRequest request;
    request.set_page_size(pageSize);
    request.set_page_token(token);
    v1::ListMeshesResponse response;
    return meshes_->ListMeshes(&context, request, &response);
  }
  grpc::Status download(const std::string& name) {
    grpc::ClientContext context;
    prepare(context, kToken);
    v1::DownloadMeshRequest request;
    request.set_name(name);
    auto reader = meshes_->DownloadMesh(&context, request);
    v1::DownloadMeshResponse message;
    while (reader->Read(&message)) {
    }
    return reader->Finish();
  }
  grpc::Status tessellate(const v1::TessellateRequest& request) {
    grpc::ClientContext context;
    prepare(context, kToken);
    auto reader = tessellation_->Tessellate(&context, request);
    v1::TessellateResponse message;
    while (reader->Read(&message)) {
    }
    return reader->Finish();
  }
  // A request for the uploaded "target" mesh with an absolute tolerance, edited by the case.
  grpc::Status tessellateWith(const std::function<void(v1::TessellateRequest&)>& edit) {
    v1::TessellateRequest request;
    request.set_name("meshes/target");
    request.set_absolute(0.01);
    edit(request);
    return tessellate(request);
  }
  static v1::Camera camera() {
    v1::Camera c;
    c.mutable_eye()->set_z(10);
    c.mutable_target();  // the origin
    c.mutable_up()->set_y(1);
    c.set_fov_y_deg(45);
    c.set_width(640);
    c.set_height(480);
    return c;
  }
  grpc::Status tessellateWithCamera(const std::function<void(v1::PixelTolerance&)>& edit) {
    return tessellateWith([&](v1::TessellateRequest& r) {
      *r.mutable_pixel()->mutable_camera() = camera();
      edit(*r.mutable_pixel());
    });
  }
  grpc::Status serverInfo(const std::string& authorization) {
    grpc::ClientContext context;
    prepare(context);
    if (!authorization.empty()) context.AddMetadata("authorization", authorization);
    v1::ServerInfo info;
    return info_->GetServerInfo(&context, {}, &info);
  }

  void runCatalogue(const std::vector<Case>& cases) {
    for (const Case& c : cases) {
      SCOPED_TRACE(c.what);
      grpc::Status status = c.call();
      EXPECT_EQ(status.error_code(), c.code) << status.error_message();
      EXPECT_NE(status.error_message().find(c.messagePart), std::string::npos)
          << "message: " << status.error_message();
      // Nothing of the server's insides reaches a client: no file or folder of it, no library's
      // own words, no source or exception text.
      for (const std::string& internal :
           {dir_.path().string(), std::string("sqlite"), std::string("postgresql:"),
            std::string("libpq"), std::string(".cpp"), std::string("std::"), std::string("what()"),
            std::string("OpenSubdiv::")}) {
        EXPECT_EQ(status.error_message().find(internal), std::string::npos)
            << "message: " << status.error_message();
      }
    }
  }

  // After the catalogue: a new client on a new channel gets correct answers.
  void expectServerStillServes() {
    ASSERT_TRUE(server_->running());
    auto channel = server_->channel();
    auto stub = v1::MeshService::NewStub(channel);
    MeshArrays mesh = gridMesh(3, 9);
    UploadResult result = uploadMessages(*stub, arraysUpload("after-catalogue", mesh), kToken);
    ASSERT_TRUE(result.status.ok()) << result.status.error_message();
    EXPECT_EQ(result.mesh.sha256(), sha256Hex(canonicalEncoding(mesh)));
    EXPECT_TRUE(get("meshes/target").ok());
    grpc::ClientContext context;
    prepare(context, kToken);
    v1::ServerInfo info;
    ASSERT_TRUE(v1::ServerInfoService::NewStub(channel)->GetServerInfo(&context, {}, &info).ok());
    EXPECT_TRUE(info.auth_required());
  }

  TempDir dir_;
  std::unique_ptr<ServerProcess> server_;
  std::unique_ptr<v1::MeshService::Stub> meshes_;
  std::unique_ptr<v1::TessellationService::Stub> tessellation_;
  std::unique_ptr<v1::ServerInfoService::Stub> info_;
  bool tessellationAvailable_ = false;
};

std::vector<v1::UploadMeshRequest> objMessages(const std::string& text) {
  return objUpload("bad-obj", text, 64 * 1024, "bad.obj");
}

MeshArrays nonManifoldFan() {
  // Three quads on the edge (0, 1): an edge shared by more than two faces.
  MeshArrays m;
  for (int i = 0; i < 8; ++i)
    m.positions.insert(m.positions.end(), {float(i), float(i % 3), float(i % 2)});
  m.faceSizes = {4, 4, 4};
  m.faceVertices = {0, 1, 2, 3, 1, 0, 4, 5, 0, 1, 6, 7};
  return m;
}

// Every edge a semi-sharp crease of sharpness 9.5: ten levels of isolation, each refining the
// whole surface again (hundreds of millions of vertices for a 20 x 20 grid).
MeshArrays creasedEverywhere(MeshArrays m) {
  std::set<std::pair<int32_t, int32_t>> edges;
  size_t start = 0;
  for (int32_t size : m.faceSizes) {
    for (int32_t k = 0; k < size; ++k) {
      const int32_t a = m.faceVertices[start + size_t(k)],
                    b = m.faceVertices[start + size_t((k + 1) % size)];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
    start += size_t(size);
  }
  for (const auto& [a, b] : edges) m.creases.push_back({a, b, 9.5f});
  return m;
}

TEST_F(BadInputCatalogue, UploadsAreRefusedWithTheStatusAndProblemNamed) {
  const MeshArrays good = gridMesh(3, 0);
  std::vector<Case> cases = {
      {"empty stream", grpc::StatusCode::INVALID_ARGUMENT, "ended before the header",
       [&] { return uploadStatus({}); }},
      {"missing header", grpc::StatusCode::INVALID_ARGUMENT, "first message must carry the header",
       [&] {
         auto messages = arraysWith(good);
         messages.erase(messages.begin());
         return uploadStatus(messages);
       }},
      {"header twice", grpc::StatusCode::INVALID_ARGUMENT, "#1: the header was already sent",
       [&] {
         auto messages = arraysWith(good);
         messages.insert(messages.begin() + 1, messages.front());
         return uploadStatus(messages);
       }},
      {"upper-case id", grpc::StatusCode::INVALID_ARGUMENT, "header.mesh_id",
       [&] { return uploadStatus(arraysUpload("Bad_Id", good)); }},
      {"empty id", grpc::StatusCode::INVALID_ARGUMENT, "header.mesh_id: a mesh id is required",
       [&] { return uploadStatus(arraysUpload("", good)); }},
      {"64-character id", grpc::StatusCode::INVALID_ARGUMENT, "header.mesh_id",
       [&] { return uploadStatus(arraysUpload(std::string(64, 'a'), good)); }},
      {"id starting with a dash", grpc::StatusCode::INVALID_ARGUMENT, "header.mesh_id",
       [&] { return uploadStatus(arraysUpload("-dash", good)); }},
      {"unspecified format", grpc::StatusCode::INVALID_ARGUMENT, "header.format",
       [&] {
         return uploadStatus(withHeader(
             arraysWith(good), [](auto& h) { h.set_format(v1::MESH_FORMAT_UNSPECIFIED); }));
       }},
      {"zero total_bytes", grpc::StatusCode::INVALID_ARGUMENT,
       "header.total_bytes: must be positive",
       [&] {
         return uploadStatus(withHeader(arraysWith(good), [](auto& h) { h.set_total_bytes(0); }));
       }},
      {"oversized upload", grpc::StatusCode::RESOURCE_EXHAUSTED, "max_upload_bytes of 2097152",
       [&] {
         return uploadStatus(
             withHeader(arraysWith(good), [](auto& h) { h.set_total_bytes(3 << 20); }));
       }},
      {"truncated stream (declared size larger than sent)", grpc::StatusCode::INVALID_ARGUMENT,
       "upload truncated: received",
       [&] {
         return uploadStatus(withHeader(
             arraysWith(good), [&](auto& h) { h.set_total_bytes(good.uploadBytes() + 100); }));
       }},
      {"an ARRAYS size no numbers add up to", grpc::StatusCode::INVALID_ARGUMENT,
       "header.total_bytes: 102 is not a multiple of 4",
       [&] {
         return uploadStatus(withHeader(arraysWith(good), [](auto& h) { h.set_total_bytes(102); }));
       }},
      {"a message over gRPC's 4 MiB limit", grpc::StatusCode::RESOURCE_EXHAUSTED, "larger than max",
       [&] {
         v1::UploadMeshRequest huge;
         huge.set_obj_data(std::string(4'500'000, '#'));
         return uploadStatus({headerMessage("bad-obj", v1::MESH_FORMAT_OBJ, 2 << 20), huge});
       }},
      {"more data than declared", grpc::StatusCode::INVALID_ARGUMENT,
       "runs past header.total_bytes",
       [&] {
         return uploadStatus(withHeader(
             arraysWith(good), [&](auto& h) { h.set_total_bytes(good.uploadBytes() - 4); }));
       }},
      {"OBJ bytes in an ARRAYS upload", grpc::StatusCode::INVALID_ARGUMENT,
       "obj_data in an upload whose header.format is ARRAYS",
       [&] {
         auto messages = arraysWith(good);
         messages[1].set_obj_data("v 0 0 0\n");
         return uploadStatus(messages);
       }},
      {"empty data message", grpc::StatusCode::INVALID_ARGUMENT, "#1: the message is empty",
       [&] {
         auto messages = arraysWith(good);
         messages.insert(messages.begin() + 1, v1::UploadMeshRequest());
         return uploadStatus(messages);
       }},
      {"positions not in triples", grpc::StatusCode::INVALID_ARGUMENT,
       "arrays.positions: 49 floats",
       [&] {
         MeshArrays m = good;
         m.positions.push_back(1.0f);
         return uploadStatus(arraysWith(m));
       }},
      {"face index out of range", grpc::StatusCode::INVALID_ARGUMENT,
       "arrays: face 1 refers to vertex 99",
       [&] {
         MeshArrays m = good;
         m.faceVertices[5] = 99;
         return uploadStatus(arraysWith(m));
       }},
      {"negative face index", grpc::StatusCode::INVALID_ARGUMENT, "refers to vertex -1",
       [&] {
         MeshArrays m = good;
         m.faceVertices[0] = -1;
         return uploadStatus(arraysWith(m));
       }},
      {"NaN coordinate", grpc::StatusCode::INVALID_ARGUMENT,
       "arrays: vertex 2 has a coordinate that is not finite",
       [&] {
         MeshArrays m = good;
         m.positions[7] = std::nanf("");
         return uploadStatus(arraysWith(m));
       }},
      {"face sizes disagree with face vertices", grpc::StatusCode::INVALID_ARGUMENT,
       "face sizes add up to",
       [&] {
         MeshArrays m = good;
         m.faceVertices.pop_back();
         return uploadStatus(arraysWith(m));
       }},
      {"two-sided face", grpc::StatusCode::INVALID_ARGUMENT, "face 0 has 2 vertices",
       [&] {
         MeshArrays m = good;
         m.faceSizes = {2, 4, 4, 4, 4, 4, 4, 4, 4, 2};
         return uploadStatus(arraysWith(m));
       }},
      {"malformed OBJ line", grpc::StatusCode::INVALID_ARGUMENT, "bad.obj:3:",
       [&] { return uploadStatus(objMessages("v 0 0 0\nv 1 0 0\nv 1 zero 0\nf 1 2 3\n")); }},
      {"OBJ face with an unknown vertex", grpc::StatusCode::INVALID_ARGUMENT, "bad.obj:4:",
       [&] { return uploadStatus(objMessages("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n")); }},
      {"unknown crease method", grpc::StatusCode::INVALID_ARGUMENT,
       "header.options.crease_method: unknown value 5",
       [&] {
         return uploadStatus(withHeader(arraysWith(good), [](auto& h) {
           h.mutable_options()->set_crease_method(static_cast<v1::CreaseMethod>(5));
         }));
       }},
      {"unknown triangle rule", grpc::StatusCode::INVALID_ARGUMENT,
       "header.options.triangle_subdivision: unknown value 9",
       [&] {
         return uploadStatus(withHeader(arraysWith(good), [](auto& h) {
           h.mutable_options()->set_triangle_subdivision(static_cast<v1::TriangleSubdivision>(9));
         }));
       }},
      {"unknown boundary interpolation", grpc::StatusCode::INVALID_ARGUMENT,
       "header.options.boundary_interpolation: unknown value 7",
       [&] {
         return uploadStatus(withHeader(arraysWith(good), [](auto& h) {
           h.mutable_options()->set_boundary_interpolation(
               static_cast<v1::BoundaryInterpolation>(7));
         }));
       }},
      {"display name too long", grpc::StatusCode::INVALID_ARGUMENT, "header.display_name",
       [&] {
         return uploadStatus(withHeader(
             arraysWith(good), [](auto& h) { h.set_display_name(std::string(300, 'x')); }));
       }},
      {"non-manifold mesh under the boundary rule none", grpc::StatusCode::UNIMPLEMENTED,
       "arrays: the mesh has 1 non-manifold edges and 2 non-manifold vertices, which are supported only with "
       "a boundary rule other than \"none\"",
       [&] {
         return uploadStatus(withHeader(arraysWith(nonManifoldFan()), [](auto& h) {
           h.mutable_options()->set_boundary_interpolation(v1::BOUNDARY_INTERPOLATION_NONE);
         }));
       }},
      {"vertices that all coincide", grpc::StatusCode::INVALID_ARGUMENT,
       "arrays: all 16 vertices coincide at (1, 1, 1): the mesh has an empty bounding box",
       [&] {
         MeshArrays m = good;
         m.positions.assign(m.positions.size(), 1.0f);
         return uploadStatus(arraysWith(m));
       }},
      {"OBJ vertices that all coincide", grpc::StatusCode::INVALID_ARGUMENT,
       "all 4 vertices coincide at (2, 0, 0): the mesh has an empty bounding box",
       [&] { return uploadStatus(objMessages("v 2 0 0\nv 2 0 0\nv 2 0 0\nv 2 0 0\nf 1 2 3 4\n")); }},
      {"more faces than the server allows", grpc::StatusCode::RESOURCE_EXHAUSTED,
       "faces; the limit is 2000", [&] { return uploadStatus(arraysWith(gridMesh(50, 0))); }},
      {"creases that would refine it into gigabytes", grpc::StatusCode::RESOURCE_EXHAUSTED,
       "over the limit of 4000000 (max_refined_vertices)",
       [&] { return uploadStatus(arraysWith(creasedEverywhere(gridMesh(20, 0)))); }},
      {"duplicate id", grpc::StatusCode::ALREADY_EXISTS, "meshes/target already exists",
       [&] { return uploadStatus(arraysUpload("target", good)); }},
      {"upload without a token", grpc::StatusCode::UNAUTHENTICATED, "missing authorization",
       [&] { return upload(arraysWith(good), "").status; }},
  };
  runCatalogue(cases);
  // None of the refused uploads left anything behind.
  EXPECT_EQ(get("meshes/bad-mesh").error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(get("meshes/bad-obj").error_code(), grpc::StatusCode::NOT_FOUND);
  expectServerStillServes();
}

TEST_F(BadInputCatalogue, NamesPagesAndAuthenticationAreChecked) {
  std::vector<Case> cases = {
      {"empty name", grpc::StatusCode::INVALID_ARGUMENT, "name: a mesh name",
       [&] { return get(""); }},
      {"name of another collection", grpc::StatusCode::INVALID_ARGUMENT,
       "name: \"widgets/x\" is not a mesh name", [&] { return get("widgets/x"); }},
      {"name with an invalid id", grpc::StatusCode::INVALID_ARGUMENT, "has an invalid mesh id",
       [&] { return get("meshes/UPPER"); }},
      {"name with a control character", grpc::StatusCode::INVALID_ARGUMENT, "\\x01",
       [&] { return get(std::string("meshes/a\x01")); }},
      {"unknown mesh", grpc::StatusCode::NOT_FOUND, "meshes/nope not found",
       [&] { return get("meshes/nope"); }},
      {"delete unknown mesh", grpc::StatusCode::NOT_FOUND, "meshes/nope not found",
       [&] { return remove("meshes/nope"); }},
      {"delete malformed name", grpc::StatusCode::INVALID_ARGUMENT,
       "name:", [&] { return remove("meshes/"); }},
      {"download malformed name", grpc::StatusCode::INVALID_ARGUMENT,
       "name:", [&] { return download("meshes/"); }},
      {"download unknown mesh", grpc::StatusCode::NOT_FOUND, "not found",
       [&] { return download("meshes/ghost"); }},
      {"negative page size", grpc::StatusCode::INVALID_ARGUMENT, "page_size",
       [&] { return list(-1, ""); }},
      {"forged page token", grpc::StatusCode::INVALID_ARGUMENT, "page_token",
       [&] { return list(10, "zz"); }},
      {"page token of a non-id", grpc::StatusCode::INVALID_ARGUMENT, "page_token",
       [&] { return list(10, "61667465723a21"); }},  // "after:!"
      {"no token", grpc::StatusCode::UNAUTHENTICATED, "missing authorization",
       [&] { return serverInfo(""); }},
      {"wrong token", grpc::StatusCode::UNAUTHENTICATED, "invalid bearer token",
       [&] { return serverInfo("Bearer not-the-token"); }},
      {"wrong scheme", grpc::StatusCode::UNAUTHENTICATED, "Bearer <token>",
       [&] { return serverInfo(std::string("Basic ") + kToken); }},
      {"token prefix only", grpc::StatusCode::UNAUTHENTICATED, "invalid bearer token",
       [&] { return serverInfo("Bearer catalogue"); }},
  };
  runCatalogue(cases);
  expectServerStillServes();
}

TEST_F(BadInputCatalogue, TessellationRequestsAreChecked) {
  std::vector<Case> cases = {
      {"unknown mesh", grpc::StatusCode::NOT_FOUND, "meshes/ghost not found",
       [&] { return tessellateWith([](auto& r) { r.set_name("meshes/ghost"); }); }},
      {"malformed name", grpc::StatusCode::INVALID_ARGUMENT,
       "name:", [&] { return tessellateWith([](auto& r) { r.set_name("ghost"); }); }},
      {"no tolerance", grpc::StatusCode::INVALID_ARGUMENT, "tolerance: one of",
       [&] { return tessellateWith([](auto& r) { r.clear_tolerance(); }); }},
      {"zero tolerance", grpc::StatusCode::INVALID_ARGUMENT, "absolute: must be positive",
       [&] { return tessellateWith([](auto& r) { r.set_absolute(0); }); }},
      {"negative tolerance", grpc::StatusCode::INVALID_ARGUMENT, "absolute: must be positive",
       [&] { return tessellateWith([](auto& r) { r.set_absolute(-1); }); }},
      {"NaN tolerance", grpc::StatusCode::INVALID_ARGUMENT, "absolute: must be a finite number",
       [&] { return tessellateWith([](auto& r) { r.set_absolute(kNaN); }); }},
      {"infinite tolerance", grpc::StatusCode::INVALID_ARGUMENT, "must be a finite number",
       [&] { return tessellateWith([](auto& r) { r.set_absolute(kInf); }); }},
      {"absurdly large tolerance", grpc::StatusCode::INVALID_ARGUMENT,
       "larger than the mesh's bounding-box diagonal",
       [&] { return tessellateWith([](auto& r) { r.set_absolute(1e30); }); }},
      {"relative tolerance of the whole diagonal", grpc::StatusCode::INVALID_ARGUMENT,
       "relative: must be below 1",
       [&] { return tessellateWith([](auto& r) { r.set_relative(1); }); }},
      {"NaN relative tolerance", grpc::StatusCode::INVALID_ARGUMENT, "relative: must be a finite",
       [&] { return tessellateWith([](auto& r) { r.set_relative(kNaN); }); }},
      // A floor no retry changes: INVALID_ARGUMENT, not RESOURCE_EXHAUSTED, in every mode.
      {"tolerance below the server's minimum", grpc::StatusCode::INVALID_ARGUMENT,
       "min_relative_tolerance",
       [&] { return tessellateWith([](auto& r) { r.set_relative(1e-12); }); }},
      {"absolute tolerance below the server's minimum", grpc::StatusCode::INVALID_ARGUMENT,
       "absolute: a tolerance of 1e-08",
       [&] { return tessellateWith([](auto& r) { r.set_absolute(1e-8); }); }},
      {"eta above 1", grpc::StatusCode::INVALID_ARGUMENT, "eta: must be in [0, 1)",
       [&] { return tessellateWith([](auto& r) { r.set_eta(1.5); }); }},
      {"NaN eta", grpc::StatusCode::INVALID_ARGUMENT, "eta",
       [&] { return tessellateWith([](auto& r) { r.set_eta(kNaN); }); }},
      {"negative eta", grpc::StatusCode::INVALID_ARGUMENT, "eta: must be in [0, 1)",
       [&] { return tessellateWith([](auto& r) { r.set_eta(-0.5); }); }},
      {"eta 0, the single-phase strategy", validCode(), validMessage(),
       [&] { return tessellateWith([](auto& r) { r.set_eta(0); }); }},
      {"uniform level 0", grpc::StatusCode::INVALID_ARGUMENT, "uniform_level",
       [&] { return tessellateWith([](auto& r) { r.set_uniform_level(0); }); }},
      {"unknown GLB encoding", grpc::StatusCode::INVALID_ARGUMENT, "encoding: unknown value 7",
       [&] { return tessellateWith([](auto& r) { r.set_encoding(v1::GlbEncoding(7)); }); }},
      {"quantized positions too coarse for the tolerance", grpc::StatusCode::INVALID_ARGUMENT,
       "quantized positions move vertices",
       [&] {
         return tessellateWith(
             [](auto& r) { r.set_relative(1e-5), r.set_encoding(v1::GLB_ENCODING_QUANTIZED); });
       }},
      {"negative max_triangles", grpc::StatusCode::INVALID_ARGUMENT,
       "max_triangles: must not be negative",
       [&] { return tessellateWith([](auto& r) { r.set_max_triangles(-5); }); }},
      {"max_triangles over the budget", grpc::StatusCode::RESOURCE_EXHAUSTED,
       "exceeds the server's max_triangles of 1000000",
       [&] { return tessellateWith([](auto& r) { r.set_max_triangles(2'000'000); }); }},
      {"camera missing", grpc::StatusCode::INVALID_ARGUMENT, "pixel.camera: is required",
       [&] { return tessellateWith([](auto& r) { r.mutable_pixel(); }); }},
      {"eye equals target", grpc::StatusCode::INVALID_ARGUMENT, "eye and target must be distinct",
       [&] {
         return tessellateWithCamera([](auto& p) { p.mutable_camera()->mutable_eye()->set_z(0); });
       }},
      {"up parallel to the view", grpc::StatusCode::INVALID_ARGUMENT, "pixel.camera.up",
       [&] {
         return tessellateWithCamera([](auto& p) {
           p.mutable_camera()->mutable_up()->set_y(0);
           p.mutable_camera()->mutable_up()->set_z(1);
         });
       }},
      {"field of view of 180 degrees", grpc::StatusCode::INVALID_ARGUMENT, "fov_y_deg",
       [&] {
         return tessellateWithCamera([](auto& p) { p.mutable_camera()->set_fov_y_deg(180); });
       }},
      {"viewport too wide", grpc::StatusCode::INVALID_ARGUMENT,
       "pixel.camera.width: must be in [1, 16384]",
       [&] { return tessellateWithCamera([](auto& p) { p.mutable_camera()->set_width(20000); }); }},
      {"zero width", grpc::StatusCode::INVALID_ARGUMENT, "pixel.camera.width",
       [&] { return tessellateWithCamera([](auto& p) { p.mutable_camera()->set_width(0); }); }},
      {"NaN eye", grpc::StatusCode::INVALID_ARGUMENT,
       "pixel.camera.eye: coordinates must be finite",
       [&] {
         return tessellateWithCamera(
             [](auto& p) { p.mutable_camera()->mutable_eye()->set_x(kNaN); });
       }},
      {"zero pixel accuracy", grpc::StatusCode::INVALID_ARGUMENT,
       "pixel_accuracy: must be positive",
       [&] { return tessellateWithCamera([](auto& p) { p.set_pixel_accuracy(0); }); }},
      {"pixels finer than the server's min_pixel_accuracy", grpc::StatusCode::INVALID_ARGUMENT,
       "pixel.pixel_accuracy: 0.01 is finer than the server's min_pixel_accuracy of 0.05",
       [&] { return tessellateWithCamera([](auto& p) { p.set_pixel_accuracy(0.01); }); }},
      // Issue 47: half a pixel through a 0.01-degree lens, 10 units away, asks ~3e-7 of the
      // 5.7-unit grid's diagonal at its nearest corner, under min_relative_tolerance (1e-6).
      {"a camera whose pixels ask below min_relative_tolerance", grpc::StatusCode::INVALID_ARGUMENT,
       "pixel: pixel accuracy 0.5 px at this camera asks 3.1e-07 of the bounding-box diagonal at the mesh's "
       "nearest point, finer than the server's minimum 1e-06 (min_relative_tolerance)",
       [&] { return tessellateWithCamera([](auto& p) { p.mutable_camera()->set_fov_y_deg(1e-2); }); }},
      {"the same camera at the coarsest pixels it allows", validCode(), validMessage(),
       [&] {
         return tessellateWithCamera([](auto& p) {
           p.mutable_camera()->set_fov_y_deg(1e-2);
           p.set_pixel_accuracy(4);
         });
       }},
      {"a valid request", validCode(), validMessage(),
       [&] { return tessellateWith([](auto&) {}); }},
      {"a uniform level without a tolerance", validCode(), validMessage(),
       [&] {
         return tessellateWith([](auto& r) {
           r.clear_tolerance();
           r.set_uniform_level(8);
         });
       }},
      {"a valid camera request", validCode(), validMessage(),
       [&] { return tessellateWithCamera([](auto&) {}); }},
  };
  runCatalogue(cases);
  expectServerStillServes();
}

TEST_F(BadInputCatalogue, DeadlinesAndCancellationEndUploadsWithoutATrace) {
  std::vector<Case> cases = {
      {"deadline passes mid-upload", grpc::StatusCode::DEADLINE_EXCEEDED, "Deadline",
       [&] {
         grpc::ClientContext context;
         prepare(context, kToken, 30);
         context.set_deadline(std::chrono::system_clock::now() + std::chrono::milliseconds(300));
         v1::Mesh mesh;
         auto writer = meshes_->UploadMesh(&context, &mesh);
         writer->Write(headerMessage("late", v1::MESH_FORMAT_OBJ, 1000));
         // No more data and no half-close: only the deadline can end this call.
         return writer->Finish();
       }},
      {"client cancels mid-upload", grpc::StatusCode::CANCELLED, "CANCELLED",
       [&] {
         grpc::ClientContext context;
         prepare(context, kToken);
         v1::Mesh mesh;
         auto writer = meshes_->UploadMesh(&context, &mesh);
         writer->Write(headerMessage("cancelled", v1::MESH_FORMAT_OBJ, 1000));
         v1::UploadMeshRequest chunk;
         chunk.set_obj_data("v 0 0 0\n");
         writer->Write(chunk);
         context.TryCancel();
         return writer->Finish();
       }},
  };
  runCatalogue(cases);
  EXPECT_EQ(get("meshes/late").error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(get("meshes/cancelled").error_code(), grpc::StatusCode::NOT_FOUND);
  expectServerStillServes();
}

// Bytes a handler never sees because they are not its request message (a broken protobuf, a
// string that is not UTF-8): INVALID_ARGUMENT naming the method, not gRPC's bare INTERNAL.
TEST_F(BadInputCatalogue, UnparsableRequestsAreInvalidArgumentsNamingTheMethod) {
  const std::vector<std::pair<std::string, std::string>> requests = {
      {"a broken protobuf", std::string("\xff\xff\xff\xff", 4)},
      {"a name that is not UTF-8", std::string("\x0a\x02\xc3\x28", 4)},
  };
  for (const auto& [what, bytes] : requests) {
    const grpc::Status status =
        rawUnaryCall(server_->channel(), "/tessera.v1.MeshService/GetMesh", bytes, kToken);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT)
        << what << ": " << status.error_message();
    EXPECT_NE(status.error_message().find("/tessera.v1.MeshService/GetMesh"), std::string::npos)
        << what << ": " << status.error_message();
  }
  EXPECT_EQ(get("meshes/target").error_code(), grpc::StatusCode::OK);
}

}  // namespace
}  // namespace tessera::test
