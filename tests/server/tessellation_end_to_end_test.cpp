// Tessellation over the network is the same computation as in-process: for each benchmark model
// (the paper's test set in TESSERA_MODELS_DIR), a mesh uploaded over gRPC and tessellated by the
// real server streams a GLB that, reassembled and checked against its SHA-256, is byte-identical
// to what `tessera tessellate MODEL.obj` writes in-process, with the same triangle count; so do a
// pixel-accurate (camera) request, a uniform-level one and a meshopt-compressed one. A cancelled tessellation stops the
// server computing. Runs on SQLite and, when TESSERA_TEST_POSTGRES_URL is set, on PostgreSQL.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "tests/server/process_memory.h"
#include "tests/server/store_fixture.h"

namespace tessera::test {
namespace {

// The relative tolerance of the issue's acceptance test.
constexpr double kRelativeTolerance = 1e-3;

struct CliRun {
  int code = -1;
  std::string output;
};

// `tessera ARGS` in-process (no --server), stdout and stderr together.
CliRun runCli(const std::string& args) {
  std::string command =
      std::string("env -u TESSERA_SERVER ") + TESSERA_CLI_BINARY + " " + args + " 2>&1";
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return run;
  char buffer[4096];
  for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) run.output.append(buffer, n);
  int status = pclose(pipe);
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

// The tolerance in the "guaranteed bound B (tolerance T)" line the local tessellate prints; -1 if absent.
double printedTolerance(const std::string& output) {
  std::smatch match;
  static const std::regex line(R"(\(tolerance ([0-9.e+-]+)\))");
  return std::regex_search(output, match, line) ? std::stod(match[1]) : -1;
}

// The "triangles  N" line the local tessellate prints; -1 if absent.
int64_t printedTriangles(const std::string& output) {
  std::smatch match;
  static const std::regex line(R"(triangles\s+(\d+))");
  return std::regex_search(output, match, line) ? std::stoll(match[1]) : -1;
}

// Triangles in a GLB written by core's writer: the count of the first primitive's index
// accessor, divided by 3, read from the JSON chunk (glTF 2.0 §4.4: 12-byte header, then the
// chunk's length, its type, its data).
int64_t glbTriangles(const std::string& glb) {
  if (glb.size() < 20) return -1;
  uint32_t jsonLength = 0;
  std::memcpy(&jsonLength, glb.data() + 12, 4);
  if (glb.size() < 20 + size_t(jsonLength)) return -1;
  auto json = nlohmann::json::parse(glb.substr(20, jsonLength), nullptr, false);
  if (json.is_discarded()) return -1;
  int indices = json["meshes"][0]["primitives"][0]["indices"].get<int>();
  return json["accessors"][indices]["count"].get<int64_t>() / 3;
}

// Whether the GLB's primitive carries TEXCOORD_0 (the mesh's UVs).
bool glbHasTexcoords(const std::string& glb) {
  uint32_t jsonLength = 0;
  if (glb.size() < 20) return false;
  std::memcpy(&jsonLength, glb.data() + 12, 4);
  auto json = nlohmann::json::parse(glb.substr(20, jsonLength), nullptr, false);
  return !json.is_discarded() && json["meshes"][0]["primitives"][0]["attributes"].contains("TEXCOORD_0");
}

const std::string kTessellateCalls =
    "tessera_requests_total{method=\"/tessera.v1.TessellationService/Tessellate\",code=";

class TessellationEndToEnd : public StoreTest {
 protected:
  void SetUp() override {
    StoreTest::SetUp();
    if (IsSkipped()) return;
    if (!std::filesystem::exists(TESSERA_CLI_BINARY)) {
      GTEST_SKIP() << "the tessera CLI was not built (" << TESSERA_CLI_BINARY << ")";
    }
  }

  void start(std::vector<std::string> flags = {}) {
    server_ = startServer(std::move(flags));
    ASSERT_TRUE(server_);
    meshes_ = v1::MeshService::NewStub(server_->channel());
    tessellation_ = v1::TessellationService::NewStub(server_->channel());
  }

  // Uploads TESSERA_MODELS_DIR/<model>.obj as meshes/<model>: the id the local CLI also names
  // the glTF mesh by (the file's stem), so that the two GLBs can be equal byte for byte.
  void upload(const std::string& model) {
    UploadResult uploaded = uploadMessages(*meshes_, objUpload(model, readFile(sourceOf(model))));
    ASSERT_TRUE(uploaded.status.ok()) << model << ": " << uploaded.status.error_message();
  }

  // Writes the in-process result of `tessera tessellate <model>.obj cliArgs` and returns it.
  std::string tessellateInProcess(const std::string& model, const std::string& cliArgs,
                                  int64_t* triangles, double* tolerance) {
    std::filesystem::path out = dir_.path() / (model + "-cli.glb");
    CliRun run = runCli("tessellate " + sourceOf(model).string() + " " + cliArgs +
                        " -o " + out.string());
    EXPECT_EQ(run.code, 0) << run.output;
    *triangles = printedTriangles(run.output);
    *tolerance = printedTolerance(run.output);
    return readFile(out);
  }

  // Tessellates meshes/<model> over gRPC and in-process and checks that both agree.
  void expectSameAsCli(const std::string& model, v1::TessellateRequest request,
                       const std::string& cliArgs) {
    SCOPED_TRACE(model + " " + cliArgs);
    request.set_name("meshes/" + model);
    Streamed remote = tessellateOverGrpc(*tessellation_, request);
    ASSERT_TRUE(remote.status.ok()) << remote.status.error_message();
    ASSERT_EQ(remote.problem, "");
    int64_t cliTriangles = -1;
    double cliTolerance = -1;
    std::string local = tessellateInProcess(model, cliArgs, &cliTriangles, &cliTolerance);
    ASSERT_FALSE(local.empty());
    EXPECT_EQ(remote.glb.size(), local.size());
    EXPECT_TRUE(remote.glb == local) << "the streamed GLB differs from the CLI's";
    EXPECT_EQ(remote.summary->triangles(), cliTriangles);
    EXPECT_EQ(remote.summary->triangles(), glbTriangles(remote.glb));
    // The tolerance used (in pixel mode the smallest piece's ε), as the CLI prints it (6 digits).
    EXPECT_NEAR(remote.summary->tolerance(), cliTolerance, 1e-5 * cliTolerance);
    // Every model's OBJ here has texture coordinates: they come back as TEXCOORD_0.
    EXPECT_TRUE(glbHasTexcoords(remote.glb));
  }

  // A model's OBJ: TESSERA_MODELS_DIR/<model>.obj unless copied under another name.
  std::filesystem::path sourceOf(const std::string& model) const {
    const auto copied = copies_.find(model);
    return copied != copies_.end() ? copied->second : modelPath(model + ".obj");
  }
  // Copies a shared model to <id>.obj in the test's directory: the CLI names the glTF mesh by the
  // file's stem, the server by the id, and the id must be a valid mesh id.
  void copyModel(const std::string& model, const std::string& id) {
    copies_[id] = dir_.path() / (id + ".obj");
    std::filesystem::copy_file(modelPath(model + ".obj"), copies_[id]);
  }

  std::map<std::string, std::filesystem::path> copies_;
  std::unique_ptr<ServerProcess> server_;
  std::unique_ptr<v1::MeshService::Stub> meshes_;
  std::unique_ptr<v1::TessellationService::Stub> tessellation_;
};

TEST_P(TessellationEndToEnd, EveryBenchmarkModelStreamsTheGlbTheCliWritesInProcess) {
  start();
  for (const char* model : {"bigguy", "monsterfrog", "armorguy", "t-rex", "car"}) {
    upload(model);
    v1::TessellateRequest request;
    request.set_relative(kRelativeTolerance);
    expectSameAsCli(model, request, fmt::format("--tolerance {:g} --relative", kRelativeTolerance));
  }
}

// Non-manifold shapes (edges with three or more faces; bow-tie vertices) pass the upload and the
// server's engine, whose GLB is the CLI's byte for byte.
TEST_P(TessellationEndToEnd, NonManifoldShapesStreamTheGlbTheCliWrites) {
  start();
  for (const auto& [shape, id] : {std::pair{"catmark_fan", "fan"}, std::pair{"catmark_nonman_verts", "bow-ties"}}) {
    copyModel(std::string("opensubdiv-shapes/") + shape, id);
    upload(id);
    v1::TessellateRequest request;
    request.set_relative(kRelativeTolerance);
    expectSameAsCli(id, request, fmt::format("--tolerance {:g} --relative", kRelativeTolerance));
  }
}

TEST_P(TessellationEndToEnd, APixelAccurateRequestMatchesTheCli) {
  start();
  upload("bigguy");
  v1::TessellateRequest request;
  v1::PixelTolerance* pixel = request.mutable_pixel();
  pixel->set_pixel_accuracy(0.5);
  v1::Camera* camera = pixel->mutable_camera();
  camera->mutable_eye()->set_x(10), camera->mutable_eye()->set_y(5),
      camera->mutable_eye()->set_z(30);
  camera->mutable_target();  // the origin, near the model's centre
  camera->mutable_up()->set_y(1);
  camera->set_fov_y_deg(40);
  camera->set_width(1280);
  camera->set_height(720);
  expectSameAsCli("bigguy", request,
                  "--eye 10,5,30 --target 0,0,0 --up 0,1,0 --fov 40 --size 1280x720 "
                  "--pixel-accuracy 0.5");
}

TEST_P(TessellationEndToEnd, AUniformLevelRequestMatchesTheCli) {
  start();
  upload("car");  // creases and boundaries
  v1::TessellateRequest request;
  request.set_uniform_level(3);
  expectSameAsCli("car", request, "--level 3");
}

TEST_P(TessellationEndToEnd, AMeshoptRequestMatchesTheCli) {
  start();
  upload("bigguy");
  v1::TessellateRequest request;
  request.set_relative(kRelativeTolerance);
  request.set_encoding(v1::GLB_ENCODING_MESHOPT);
  expectSameAsCli("bigguy", request, fmt::format("--tolerance {:g} --relative --encoding meshopt", kRelativeTolerance));
}

// The job: armorguy at the finest tolerance that fits the default triangle budget, so that
// finishing it would take the server seconds and gigabytes. It is cancelled once the server says
// it is tessellating, i.e. inside core's tessellate(), which polls the call's cancellation.
// What shows that the computation stopped, rather than ran on and was thrown away: the server's
// peak memory does not grow by even the size of the index buffer the finished job would hold;
// and the only slot (--max-concurrent-jobs 1) is free for the next request, which succeeds.
TEST_P(TessellationEndToEnd, CancellingATessellationStopsTheServerComputing) {
  start({"--max-concurrent-jobs", "1"});
  upload("armorguy");
  upload("bigguy");
  v1::TessellateRequest heavy;
  heavy.set_name("meshes/armorguy");
  heavy.set_relative(1e-5);

  // The server's own estimate of the job, from a request refused for its budget; this also
  // preprocesses the mesh and plans the job once, so that neither counts against the peak below.
  v1::TessellateRequest probe = heavy;
  probe.set_max_triangles(1);
  Streamed refused = tessellateOverGrpc(*tessellation_, probe);
  ASSERT_EQ(refused.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  std::smatch match;
  std::string message = refused.status.error_message();
  ASSERT_TRUE(std::regex_search(message, match, std::regex(R"(about (\d+) triangles)"))) << message;
  const int64_t estimate = std::stoll(match[1]);
  const int64_t peakBefore = processMemoryBytes(server_->pid(), "VmHWM");
  ASSERT_GT(peakBefore, 0);

  grpc::ClientContext context;
  prepare(context, {}, 300);
  auto reader = tessellation_->Tessellate(&context, heavy);
  v1::TessellateResponse response;
  bool tessellating = false;
  while (!tessellating && reader->Read(&response)) {
    tessellating = response.has_progress() && response.progress().stage() == "tessellating";
  }
  ASSERT_TRUE(tessellating) << "the stream ended before the job started tessellating";
  context.TryCancel();
  EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::CANCELLED);

  // The next request needs the only slot, so it is answered only once the cancelled job let go.
  v1::TessellateRequest next;
  next.set_name("meshes/bigguy");
  next.set_relative(1e-2);
  Streamed answered = tessellateOverGrpc(*tessellation_, next);
  ASSERT_TRUE(answered.status.ok()) << answered.status.error_message();
  EXPECT_EQ(answered.problem, "");

  // A finished job holds 3 uint32 indices per triangle, besides its vertices and the GLB.
  const int64_t indexBytes = estimate * 12;
  const int64_t peakGrowth = processMemoryBytes(server_->pid(), "VmHWM") - peakBefore;
  RecordProperty("estimated_triangles", std::to_string(estimate));
  RecordProperty("peak_memory_growth_bytes", std::to_string(peakGrowth));
  EXPECT_LT(peakGrowth, indexBytes)
      << "the server's peak memory grew by " << peakGrowth
      << " bytes; the finished job's indices alone take " << indexBytes;

  // The server counts a call when gRPC releases it, which may come a little after the client has
  // its status: poll (bounded) rather than read once.
  std::string metrics;
  for (int attempt = 0; attempt < 100; ++attempt) {
    metrics = httpGet(server_->metricsAddress(), "/metrics");
    if (seriesValue(metrics, kTessellateCalls + "\"CANCELLED\"}") == 1 &&
        seriesValue(metrics, kTessellateCalls + "\"OK\"}") == 1) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_EQ(seriesValue(metrics, kTessellateCalls + "\"CANCELLED\"}"), 1) << metrics;
  EXPECT_EQ(seriesValue(metrics, kTessellateCalls + "\"OK\"}"), 1) << metrics;
  EXPECT_EQ(seriesValue(metrics, "tessera_jobs_running"), 0) << metrics;
  // Only the answered request's triangles were ever delivered.
  EXPECT_EQ(seriesValue(metrics, "tessera_triangles_produced_total"),
            double(answered.summary->triangles()));
  EXPECT_NE(server_->log().find("method=/tessera.v1.TessellationService/Tessellate "
                                "status=CANCELLED"),
            std::string::npos)
      << server_->log();
}

TESSERA_INSTANTIATE_STORE_TESTS(TessellationEndToEnd);

}  // namespace
}  // namespace tessera::test
