// The `tessera` CLI's remote commands against a real server: what they print, the files they
// write and their exit codes (client/commands.h). Skipped when the CLI was not built.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

// Exit codes from client/commands.h.
constexpr int kExitOk = 0;
constexpr int kExitUsage = 2;
constexpr int kExitInvalidInput = 3;
constexpr int kExitLimit = 5;
constexpr int kExitRemote = 7;

struct CliRun {
  int code;
  std::string output;
};

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(TESSERA_CLI_BINARY)) {
      GTEST_SKIP() << "the tessera CLI was not built (" << TESSERA_CLI_BINARY << ")";
    }
  }

  void startServer(std::vector<std::string> flags = {}) {
    flags.insert(flags.end(), {"--store", "sqlite:" + (dir_.path() / "m.db").string()});
    server_ = ServerProcess::start(dir_.path(), flags);
    ASSERT_TRUE(server_);
  }

  // Runs `tessera --server ADDRESS args` with stderr folded into the output.
  CliRun tessera(const std::string& args, const std::string& environment = "") {
    return run(" --server " + server_->address() + " " + args, environment);
  }

  // Runs `tessera args` (a local command: no server).
  CliRun run(const std::string& args, const std::string& environment = "") {
    std::string command = "env -u TESSERA_SERVER -u TESSERA_TOKEN " + environment + " " +
                          TESSERA_CLI_BINARY + " " + args + " 2>&1";
    CliRun run{-1, ""};
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return run;
    char buffer[4096];
    for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) run.output.append(buffer, n);
    int status = pclose(pipe);
    run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return run;
  }

  TempDir dir_;
  std::unique_ptr<ServerProcess> server_;
};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST_F(CliTest, InspectDescribesNonManifoldShapesAndRefusals) {
  const std::string shapes = modelPath("opensubdiv-shapes").string() + "/";
  CliRun fan = run("inspect --json " + shapes + "catmark_fan.obj");
  ASSERT_EQ(fan.code, kExitOk) << fan.output;
  const nlohmann::json report = nlohmann::json::parse(fan.output, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << fan.output;
  EXPECT_TRUE(report["refused"].is_null());
  EXPECT_GT(report["non_manifold_edges"].get<int>(), 0);
  EXPECT_GT(report["regular_patches"].get<int>(), 0);
  CliRun text = run("inspect " + shapes + "catmark_nonman_verts.obj");
  ASSERT_EQ(text.code, kExitOk) << text.output;
  EXPECT_TRUE(contains(text.output, "non-manifold        0 edges,")) << text.output;  // bow-ties only
  EXPECT_FALSE(contains(text.output, "refused")) << text.output;
  CliRun manifold = run("inspect " + shapes + "catmark_cube.obj");
  EXPECT_FALSE(contains(manifold.output, "non-manifold")) << manifold.output;
  CliRun edit = run("inspect " + shapes + "catmark_square_hedit0.obj");
  EXPECT_NE(edit.code, kExitOk);
  EXPECT_TRUE(contains(edit.output, "vertexedit")) << edit.output;
}

TEST_F(CliTest, UploadListGetDeleteInfoAndHealth) {
  startServer();
  CliRun upload = tessera("upload " + modelPath("bigguy.obj").string() + " --name bigguy");
  EXPECT_EQ(upload.code, kExitOk) << upload.output;
  EXPECT_TRUE(contains(upload.output, "meshes/bigguy")) << upload.output;
  EXPECT_TRUE(contains(upload.output, "1452")) << upload.output;

  CliRun list = tessera("list --page-size 1");
  EXPECT_EQ(list.code, kExitOk) << list.output;
  EXPECT_TRUE(contains(list.output, "meshes/bigguy")) << list.output;

  CliRun get = tessera("get meshes/bigguy");
  EXPECT_EQ(get.code, kExitOk) << get.output;
  EXPECT_TRUE(contains(get.output, "1450")) << get.output;

  CliRun info = tessera("info");
  EXPECT_EQ(info.code, kExitOk) << info.output;
  EXPECT_TRUE(contains(info.output, "tessellation  available")) << info.output;
  EXPECT_TRUE(contains(info.output, "cpu")) << info.output;

  CliRun health = tessera("health");
  EXPECT_EQ(health.code, kExitOk) << health.output;
  EXPECT_TRUE(contains(health.output, "SERVING")) << health.output;

  CliRun removed = tessera("delete meshes/bigguy");
  EXPECT_EQ(removed.code, kExitOk) << removed.output;
  CliRun missing = tessera("get meshes/bigguy");
  EXPECT_EQ(missing.code, kExitRemote);
  EXPECT_TRUE(contains(missing.output, "NOT_FOUND: mesh meshes/bigguy not found")) << missing.output;
}

// The value after `label` on its line of the CLI's mesh printout.
std::string printed(const std::string& output, const std::string& label) {
  const size_t at = output.find("\n" + label);
  if (at == std::string::npos) return "";
  const size_t start = output.find_first_not_of(' ', at + 1 + label.size());
  return output.substr(start, output.find('\n', start) - start);
}

// bigguy.obj with every vertex moved (its y scaled) and, when asked, one texture coordinate
// changed: an edited cage as a modelling tool exports it.
std::string editedBigguy(bool newUv) {
  std::istringstream in(readFile(modelPath("bigguy.obj")));
  std::string out;
  bool uvChanged = false;
  for (std::string line; std::getline(in, line);) {
    float x, y, z;
    if (line.rfind("v ", 0) == 0 && std::sscanf(line.c_str(), "v %f %f %f", &x, &y, &z) == 3) {
      line = fmt::format("v {} {} {}", x, y * 1.02f + 0.01f, z);
    } else if (newUv && !uvChanged && line.rfind("vt ", 0) == 0) {
      line = "vt 0.123 0.456", uvChanged = true;
    }
    out += line + "\n";
  }
  return out;
}

// `upload --topology-of`: the file's topology is checked here against the stored mesh's, only
// its positions (and UVs that changed) are sent, and the mesh is the full upload's.
TEST_F(CliTest, UploadTopologyOfSendsThePositionsOfTheSameMesh) {
  startServer();
  ASSERT_EQ(tessera("upload " + modelPath("bigguy.obj").string() + " --name bigguy").code, kExitOk);
  auto stub = v1::MeshService::NewStub(server_->channel());
  for (bool newUv : {false, true}) {
    SCOPED_TRACE(newUv ? "a UV changed" : "positions only");
    const std::string file = (dir_.path() / (newUv ? "uv.obj" : "edit.obj")).string();
    std::ofstream(file) << editedBigguy(newUv);
    const std::string id = newUv ? "uv" : "edit";
    CliRun positions = tessera("upload " + file + " --name " + id + " --topology-of meshes/bigguy");
    ASSERT_EQ(positions.code, kExitOk) << positions.output;
    EXPECT_TRUE(contains(positions.output, newUv ? "positions and UVs of meshes/bigguy" : "(positions of meshes/bigguy"))
        << positions.output;
    CliRun full = tessera("upload " + file + " --name " + id + "-full");
    ASSERT_EQ(full.code, kExitOk) << full.output;
    EXPECT_EQ(printed(positions.output, "sha256"), printed(full.output, "sha256"));
    EXPECT_EQ(printed(positions.output, "sha256").size(), 64u);
    // 12 bytes a vertex (and 8 a UV): what the server counted as the upload's size.
    v1::Mesh stored;
    grpc::Status status;
    const MeshArrays parent = downloadMesh(*stub, "bigguy", &status);
    downloadMesh(*stub, id, &status, &stored);
    ASSERT_TRUE(status.ok()) << status.error_message();
    EXPECT_EQ(stored.source_bytes(), int64_t(4 * parent.positions.size() + (newUv ? 4 * parent.uvs.size() : 0)));
  }
  // Another model's topology, and a mesh that is not there.
  CliRun other = tessera("upload " + modelPath("car.obj").string() + " --name car --topology-of meshes/bigguy");
  EXPECT_EQ(other.code, kExitInvalidInput) << other.output;
  EXPECT_TRUE(contains(other.output, "vertices, meshes/bigguy has 1452: not its topology")) << other.output;
  CliRun missing = tessera("upload " + modelPath("bigguy.obj").string() + " --name x --topology-of nope");
  EXPECT_EQ(missing.code, kExitRemote) << missing.output;
  EXPECT_TRUE(contains(missing.output, "NOT_FOUND")) << missing.output;
  EXPECT_TRUE(contains(missing.output, "meshes/nope")) << missing.output;
}

TEST_F(CliTest, ErrorsPrintTheStatusCodeNameAndMessage) {
  startServer();
  ASSERT_EQ(tessera("upload " + modelPath("bigguy.obj").string() + " --name bigguy").code, kExitOk);
  CliRun unknown = tessera("tessellate meshes/ghost --tolerance 0.01 -o " +
                           (dir_.path() / "out.glb").string());
  EXPECT_EQ(unknown.code, kExitRemote) << unknown.output;
  EXPECT_TRUE(contains(unknown.output, "NOT_FOUND: mesh meshes/ghost not found")) << unknown.output;
  // A failed call leaves no output file, not even a partial one.
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "out.glb"));
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "out.glb.partial"));

  CliRun tooFine = tessera("tessellate meshes/bigguy --tolerance 1e-9 --relative -o x.glb");
  EXPECT_EQ(tooFine.code, kExitInvalidInput) << tooFine.output;
  EXPECT_TRUE(contains(tooFine.output, "INVALID_ARGUMENT: relative:")) << tooFine.output;

  CliRun noTolerance = tessera("tessellate meshes/bigguy -o x.glb");
  EXPECT_EQ(noTolerance.code, kExitUsage) << noTolerance.output;
  EXPECT_TRUE(contains(noTolerance.output, "give --tolerance, --level, or a camera"))
      << noTolerance.output;

  CliRun camera = tessera("tessellate meshes/bigguy --eye 0,0,10 --target 0,0,0 --fov 0 -o " +
                          (dir_.path() / "cam.glb").string());
  EXPECT_EQ(camera.code, kExitInvalidInput) << camera.output;
  EXPECT_TRUE(contains(camera.output, "INVALID_ARGUMENT: pixel.camera.fov_y_deg")) << camera.output;
}

TEST_F(CliTest, TessellateWritesTheStreamedFileAfterCheckingIt) {
  startServer({"--test-engine", "pattern"});
  ASSERT_EQ(tessera("upload " + modelPath("bigguy.obj").string() + " --name bigguy").code, kExitOk);
  std::filesystem::path out = dir_.path() / "bigguy.glb";
  CliRun run = tessera("tessellate meshes/bigguy --tolerance 0.001 --relative -o " + out.string());
  EXPECT_EQ(run.code, kExitOk) << run.output;
  std::string written = readFile(out);
  ASSERT_EQ(written.size(), 200'003u);  // the pattern engine's output (server/tessellation/test_engines.h)
  EXPECT_EQ(static_cast<uint8_t>(written[1000]), static_cast<uint8_t>((1000 * 131 + (1000 >> 8)) & 0xff));
}

// A result asked into a file that is not a regular one (a FIFO here; /dev/null alike) is written
// through it, not staged beside it and renamed over it: as root that rename replaced /dev/null
// with a regular file for the whole machine.
TEST_F(CliTest, TessellateIntoAFifoWritesThroughItAndLeavesItAFifo) {
  startServer({"--test-engine", "pattern"});
  ASSERT_EQ(tessera("upload " + modelPath("bigguy.obj").string() + " --name bigguy").code, kExitOk);
  const std::filesystem::path fifo = dir_.path() / "out.fifo";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  // Held open for reading and writing: the command's open finds a reader, and reads never end.
  const int fd = open(fifo.c_str(), O_RDWR | O_NONBLOCK);
  ASSERT_GE(fd, 0);
  std::string received;
  std::atomic<bool> finished{false};
  std::thread reader([&] {
    char buffer[65536];
    for (;;) {
      pollfd ready{fd, POLLIN, 0};
      if (poll(&ready, 1, 200) > 0) {
        const ssize_t n = read(fd, buffer, sizeof buffer);
        if (n > 0) received.append(buffer, size_t(n));
      } else if (finished) {
        return;  // nothing for 200 ms after the command ended
      }
    }
  });
  const CliRun run = tessera("tessellate meshes/bigguy --tolerance 0.001 --relative -o " + fifo.string());
  finished = true;
  reader.join();
  close(fd);
  EXPECT_EQ(run.code, kExitOk) << run.output;
  EXPECT_EQ(received.size(), 200'003u);  // the pattern engine's output
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  EXPECT_FALSE(std::filesystem::exists(fifo.string() + ".partial"));
}

TEST_F(CliTest, TheTokenComesFromTheEnvironment) {
  startServer({"--token", "cli-secret"});
  CliRun refused = tessera("list");
  EXPECT_EQ(refused.code, kExitRemote);
  EXPECT_TRUE(contains(refused.output, "UNAUTHENTICATED")) << refused.output;
  CliRun accepted = tessera("list", "TESSERA_TOKEN=cli-secret");
  EXPECT_EQ(accepted.code, kExitOk) << accepted.output;
}

// A busy server refuses with a retry hint (grpc-retry-pushback-ms); the load tester's workers wait
// that long (jittered) before their next request instead of hammering it, and report the useful
// throughput beside the offered one. One job slot, no queue, jobs that last the call's 1 s
// deadline: four workers for 3 s get a handful of refusals each when they back off (the hint is
// about a job's length), thousands when they do not.
TEST_F(CliTest, BenchBacksOffWhenTheServerIsBusy) {
  startServer({"--test-engine", "block", "--max-concurrent-jobs", "1", "--max-queued-jobs", "0"});
  auto meshes = v1::MeshService::NewStub(server_->channel());
  ASSERT_TRUE(uploadMessages(*meshes, arraysUpload("grid", gridMesh(4, 0))).status.ok());
  const std::filesystem::path json = dir_.path() / "bench.json";
  CliRun run = tessera("bench --mix tessellate=1 --mesh meshes/grid --tolerance 0.01 --relative "
                       "--concurrency 4 --requests 1000000 --duration 3s --timeout 1s --json " + json.string());
  ASSERT_TRUE(std::filesystem::exists(json)) << run.output;
  const nlohmann::json level = nlohmann::json::parse(readFile(json))["levels"][0];
  const int64_t refused = level["errors"].value("RESOURCE_EXHAUSTED", int64_t(0));
  EXPECT_GT(refused, 0) << level.dump();
  EXPECT_LT(refused, 400) << level.dump();
  EXPECT_TRUE(level.contains("ok_rps")) << level.dump();
  EXPECT_TRUE(contains(run.output, "OK/S")) << run.output;
}

// The cold mix uploads content the server has never seen and tessellates each mesh once: the
// server preprocesses every one (its patch-set cache misses once per copy, which it would not for
// copies of equal content under new ids), each copy is the source moved by a small displacement
// and no more, and the copies stay, so that the same seed again is refused instead of served warm.
TEST_F(CliTest, BenchColdMixPreprocessesEveryUpload) {
  startServer();
  auto meshes = v1::MeshService::NewStub(server_->channel());
  const MeshArrays grid = gridMesh(6, 0);
  ASSERT_TRUE(uploadMessages(*meshes, arraysUpload("grid", grid)).status.ok());
  auto misses = [&] {
    return seriesValue(httpGet(server_->metricsAddress(), "/metrics"),
                       "tessera_patch_cache_misses_total");
  };
  ASSERT_EQ(misses(), 0);
  constexpr int kCold = 4;  // per level, over two levels
  const std::filesystem::path json = dir_.path() / "cold.json";
  CliRun run = tessera("bench --cold " + std::to_string(kCold) +
                       " --mesh meshes/grid --tolerance 0.01 --relative --concurrency 1,2 --json " +
                       json.string());
  ASSERT_EQ(run.code, kExitOk) << run.output;
  EXPECT_TRUE(contains(run.output, "upload")) << run.output;
  const nlohmann::json report = nlohmann::json::parse(readFile(json));
  EXPECT_EQ(report["cold"]["meshes_per_level"], kCold);
  ASSERT_EQ(report["levels"].size(), 2u);
  for (const nlohmann::json& level : report["levels"]) {
    EXPECT_TRUE(level["errors"].empty()) << level.dump();
    EXPECT_EQ(level["operations"]["upload"]["ok"], kCold) << level.dump();
    EXPECT_EQ(level["operations"]["tessellate"]["ok"], kCold) << level.dump();
    EXPECT_FALSE(level["operations"]["tessellate"]["latency_ms"].is_null()) << level.dump();
  }
  EXPECT_EQ(misses(), 2 * kCold);

  grpc::Status status;
  const MeshArrays copy = downloadMesh(*meshes, "bench-cold-0-5", &status);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(copy.faceSizes, grid.faceSizes);
  EXPECT_EQ(copy.faceVertices, grid.faceVertices);
  ASSERT_EQ(copy.positions.size(), grid.positions.size());
  float lo = grid.positions[0], hi = grid.positions[0], moved = 0;
  for (size_t i = 0; i < grid.positions.size(); ++i) {
    lo = std::min(lo, grid.positions[i]), hi = std::max(hi, grid.positions[i]);
    moved = std::max(moved, std::abs(copy.positions[i] - grid.positions[i]));
  }
  EXPECT_GT(moved, 0);
  // 3e-3 of the diagonal at most per axis (remote_cold_copies.h); the diagonal is at least the
  // widest extent and at most sqrt(3) times it.
  EXPECT_LE(moved, 3e-3 * std::sqrt(3.0) * (hi - lo) * 1.001);

  CliRun again = tessera(
      "bench --cold 1 --mesh meshes/grid --tolerance 0.01 --relative --concurrency 1 --json " +
      json.string());
  ASSERT_EQ(again.code, kExitOk) << again.output;
  const nlohmann::json refused = nlohmann::json::parse(readFile(json))["levels"][0];
  EXPECT_EQ(refused["errors"].value("ALREADY_EXISTS", 0), 1) << refused.dump();
  EXPECT_EQ(misses(), 2 * kCold);
}

}  // namespace
}  // namespace tessera::test
