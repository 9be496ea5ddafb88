// --engine against the real server: which engine runs is named in GetServerInfo and in the
// metrics; cpu and auto (the CUDA engine where a device answers) stream the same GLB; cuda
// without a device, or an unknown engine, stops the server with the reason.
#include <gtest/gtest.h>

#include <string>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

namespace v1 = tessera::v1;

struct Started {
  std::unique_ptr<ServerProcess> server;
  v1::ServerInfo info;
};

Started startWithEngine(const TempDir& dir, const std::string& engine) {
  Started s;
  s.server = ServerProcess::start(dir.path(), {"--store", "sqlite:" + (dir.path() / (engine + ".db")).string(),
                                               "--engine", engine});
  auto stub = v1::ServerInfoService::NewStub(s.server->channel());
  grpc::ClientContext context;
  prepare(context);
  EXPECT_TRUE(stub->GetServerInfo(&context, {}, &s.info).ok());
  return s;
}

// The GLB of meshes/bigguy at 1e-3 of its diagonal.
std::string bigguyGlb(const ServerProcess& server) {
  auto meshes = v1::MeshService::NewStub(server.channel());
  EXPECT_TRUE(uploadModel(*meshes, "bigguy").status.ok());
  auto tessellation = v1::TessellationService::NewStub(server.channel());
  v1::TessellateRequest request;
  request.set_name("meshes/bigguy");
  request.set_relative(1e-3);
  Streamed streamed = tessellateOverGrpc(*tessellation, request);
  EXPECT_TRUE(streamed.status.ok()) << streamed.status.error_message();
  EXPECT_EQ(streamed.problem, "");
  return streamed.glb;
}

// The engine's device as GetServerInfo's device line names it ("...; tessellation device: D; ..."),
// empty when the line names none.
std::string tessellationDevice(const v1::ServerInfo& info) {
  const std::string key = "tessellation device: ";
  const size_t at = info.device().find(key);
  if (at == std::string::npos) return {};
  const size_t from = at + key.size();
  return info.device().substr(from, info.device().find("; ", from) - from);
}

std::string engineInfoSeries(const Started& s) {
  return "tessera_engine_info{engine=\"" + s.info.backends(0).name() + "\",device=\"" + tessellationDevice(s.info) +
         "\"}";
}

TEST(EngineChoice, CpuAndAutoAreNamedAndStreamTheSameGlb) {
  TempDir dir;
  const Started cpu = startWithEngine(dir, "cpu");
  const Started automatic = startWithEngine(dir, "auto");
  ASSERT_GE(cpu.info.backends_size(), 1);
  ASSERT_GE(automatic.info.backends_size(), 1);
  EXPECT_EQ(cpu.info.backends(0).name(), "cpu");
  EXPECT_EQ(tessellationDevice(cpu.info), "") << cpu.info.device();
  const std::string chosen = automatic.info.backends(0).name();
  if (chosen == "cpu") {
    // Why not CUDA: no device, or a build without it.
    EXPECT_NE(automatic.info.backends(0).detail().find("--engine auto: no CUDA"), std::string::npos)
        << automatic.info.backends(0).detail();
  } else {
    EXPECT_EQ(chosen, "cuda");
    EXPECT_NE(tessellationDevice(automatic.info), "") << automatic.info.device();
  }
  for (const Started* s : {&cpu, &automatic}) {
    const std::string page = httpGet(s->server->metricsAddress(), "/metrics");
    EXPECT_EQ(seriesValue(page, engineInfoSeries(*s)), 1.0) << engineInfoSeries(*s) << "\n" << page;
  }
  const std::string expected = bigguyGlb(*cpu.server);
  ASSERT_GT(expected.size(), 1000u);
  EXPECT_TRUE(bigguyGlb(*automatic.server) == expected) << "the " << chosen << " engine's GLB differs from the CPU's";
}

TEST(EngineChoice, CudaWithoutADeviceOrAnUnknownEngineStopsTheServer) {
  TempDir dir;
  auto [unknownCode, unknownOutput] = failedStart(dir.path(), "--engine gpu");
  EXPECT_EQ(unknownCode, 2);
  EXPECT_NE(unknownOutput.find("--engine"), std::string::npos) << unknownOutput;
  if (startWithEngine(dir, "auto").info.backends(0).name() == "cuda") GTEST_SKIP() << "a CUDA device is present";
  auto [code, output] = failedStart(dir.path(), "--engine cuda --store sqlite:" + (dir.path() / "c.db").string());
  EXPECT_EQ(code, 1);
  EXPECT_NE(output.find("--engine cuda: no CUDA"), std::string::npos) << output;
}

}  // namespace
}  // namespace tessera::test
