// `tessera render` against the real server: the files it writes decode to the requested size,
// --turntable writes one file per camera, and its exit codes follow client/commands.h.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/render_server/render_test_support.h"

extern char** environ;

namespace tessera::test {
namespace {

class RenderCliTest : public RenderServerTest {
 protected:
  struct Run {
    int exitCode = -1;
    std::string output;  // stdout and stderr
  };

  // Runs `tessera --server ADDRESS render ARGS...`, its output in a file of the temporary folder.
  Run renderCli(const std::vector<std::string>& args) {
    std::vector<std::string> argv = {TESSERA_CLI_BINARY, "--server", server().address(), "render"};
    argv.insert(argv.end(), args.begin(), args.end());
    std::filesystem::path log = dir_.path() / "cli.log";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    std::vector<char*> raw;
    for (std::string& a : argv) raw.push_back(a.data());
    raw.push_back(nullptr);
    pid_t pid = -1;
    Run run;
    if (posix_spawn(&pid, raw[0], &actions, nullptr, raw.data(), environ) == 0) {
      int status = 0;
      waitpid(pid, &status, 0);
      run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    posix_spawn_file_actions_destroy(&actions);
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    run.output = text.str();
    return run;
  }

  static std::string vec(const Vec3d& v) {
    std::ostringstream s;
    s.precision(17);
    s << v.x << "," << v.y << "," << v.z;
    return s.str();
  }

  std::vector<std::string> cameraArgs(const tessera::Camera& c) {
    return {"--eye",    vec(c.eye),
            "--target", vec(c.target),
            "--up",     vec(c.up),
            "--fov",    std::to_string(c.fovYDegrees),
            "--size",   std::to_string(c.width) + "x" + std::to_string(c.height)};
  }

  // CLI11's answers when `render` is not a subcommand of this tessera.
  void expectRenderCommand(const Run& run) {
    bool unknown = run.output.find("A subcommand is required") != std::string::npos ||
                   run.output.find("not expected: render") != std::string::npos;
    ASSERT_FALSE(unknown) << "this tessera has no `render` command: registerRenderCommand(app, "
                             "context) belongs in registerRemoteCommands "
                             "(client/remote_commands.cpp)\n"
                          << run.output;
  }

  TempDir dir_;
};

TEST_F(RenderCliTest, RenderWritesAPngAndPrintsTheStageTimings) {
  tessera::Camera camera = framedCamera({0.3, 0.4, 1}, 128, 96);
  std::filesystem::path file = dir_.path() / "bigguy.png";
  std::vector<std::string> args = {"meshes/bigguy", "-o", file.string()};
  for (const std::string& a : cameraArgs(camera)) args.push_back(a);
  Run run = renderCli(args);
  expectRenderCommand(run);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  DecodedImage image = decodeImageFile(file.string());
  EXPECT_EQ(image.width, 128);
  EXPECT_EQ(image.height, 96);
  EXPECT_GE(intersectionOverUnion(coverage(image), coverage(referenceFrame(camera).frame)), 0.999);
  for (const char* stage : {"plan", "tessellation", "raster+shading", "crack filling", "encode"}) {
    EXPECT_NE(run.output.find(stage), std::string::npos) << stage << " missing from:\n"
                                                         << run.output;
  }
  EXPECT_FALSE(std::filesystem::exists(file.string() + ".partial"));
}

TEST_F(RenderCliTest, TurntableWritesOneFilePerCamera) {
  tessera::Camera camera = framedCamera({0, 0.3, 1}, 64, 64);
  std::filesystem::path pattern = dir_.path() / "spin.png";
  std::vector<std::string> args = {"meshes/bigguy", "--turntable", "3", "-o", pattern.string()};
  for (const std::string& a : cameraArgs(camera)) args.push_back(a);
  Run run = renderCli(args);
  expectRenderCommand(run);
  ASSERT_EQ(run.exitCode, 0) << run.output;
  std::vector<DecodedImage> images;
  for (const char* name : {"spin-000.png", "spin-001.png", "spin-002.png"}) {
    ASSERT_TRUE(std::filesystem::exists(dir_.path() / name)) << name << "\n" << run.output;
    images.push_back(decodeImageFile((dir_.path() / name).string()));
    EXPECT_EQ(images.back().width, 64);
    EXPECT_GT(count(coverage(images.back())), 0u);
  }
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "spin-003.png"));
  EXPECT_FALSE(std::filesystem::exists(pattern));
  // The first camera is --eye itself; the others see bigguy from 120 and 240 degrees around.
  EXPECT_GE(intersectionOverUnion(coverage(images[0]), coverage(referenceFrame(camera).frame)),
            0.999);
  EXPECT_NE(images[0].bytes, images[1].bytes);
  EXPECT_NE(images[1].bytes, images[2].bytes);
}

TEST_F(RenderCliTest, ExitCodesFollowTheServersAnswer) {
  std::filesystem::path file = dir_.path() / "x.png";
  Run bad =
      renderCli({"meshes/bigguy", "--eye", "0,0,5", "--target", "0,0,5", "-o", file.string()});
  expectRenderCommand(bad);
  EXPECT_EQ(bad.exitCode, 3) << bad.output;  // kExitInvalidInput
  EXPECT_NE(bad.output.find("cameras[0]"), std::string::npos) << bad.output;
  Run missing = renderCli(
      {"meshes/nothing-here", "--eye", "0,0,5", "--target", "0,0,0", "-o", file.string()});
  EXPECT_EQ(missing.exitCode, 7) << missing.output;  // kExitRemote
  Run usage =
      renderCli({"meshes/bigguy", "--eye", "0,0", "--target", "0,0,0", "-o", file.string()});
  EXPECT_EQ(usage.exitCode, 2) << usage.output;  // kExitUsage
  EXPECT_FALSE(std::filesystem::exists(file));
}

}  // namespace
}  // namespace tessera::test
