// tessera-server's settings: a config file, environment variables and flags, in that order of
// strength reversed (flag > file > environment), and refusal of unknown or invalid settings.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

// The declared size of a 2000-byte upload is checked against max-upload-bytes first, so the
// refusal's message shows the limit in force.
std::string uploadLimitMessage(ServerProcess& server) {
  auto stub = v1::MeshService::NewStub(server.channel());
  UploadResult result = uploadMessages(*stub, {headerMessage("big", v1::MESH_FORMAT_OBJ, 2000)});
  EXPECT_EQ(result.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  return result.status.error_message();
}

TEST(Config, AConfigFileSetsLimitsAndFlagsOverrideIt) {
  TempDir dir;
  std::filesystem::path config = dir.path() / "tessera.toml";
  std::ofstream(config) << "# limits for a small box\nmax-upload-bytes = 1000\n"
                           "store = \"sqlite:" << (dir.path() / "m.db").string() << "\"\n";
  auto fromFile = ServerProcess::start(dir.path(), {"--config", config.string()});
  ASSERT_TRUE(fromFile);
  EXPECT_NE(uploadLimitMessage(*fromFile).find("max_upload_bytes of 1000"), std::string::npos);
  fromFile->terminate();

  auto flagWins = ServerProcess::start(dir.path(),
                                       {"--config", config.string(), "--max-upload-bytes", "1500"},
                                       {{"TESSERA_MAX_UPLOAD_BYTES", "1200"}});
  ASSERT_TRUE(flagWins);
  EXPECT_NE(uploadLimitMessage(*flagWins).find("max_upload_bytes of 1500"), std::string::npos);
}

TEST(Config, EnvironmentVariablesSetWhatNoFlagSets) {
  TempDir dir;
  auto server = ServerProcess::start(dir.path(), {},
                                     {{"TESSERA_MAX_UPLOAD_BYTES", "1200"},
                                      {"TESSERA_STORE", "sqlite:" + (dir.path() / "e.db").string()}});
  ASSERT_TRUE(server);
  EXPECT_NE(uploadLimitMessage(*server).find("max_upload_bytes of 1200"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "e.db"));
}

TEST(Config, UnknownOrInvalidSettingsStopTheServerWithAReason) {
  TempDir dir;
  std::filesystem::path config = dir.path() / "bad.toml";
  std::ofstream(config) << "max-upload-byte = 1000\n";
  auto [unknownCode, unknownOutput] = failedStart(dir.path(), "--config " + config.string());
  EXPECT_EQ(unknownCode, 2);
  EXPECT_NE(unknownOutput.find("max-upload-byte"), std::string::npos) << unknownOutput;

  auto [storeCode, storeOutput] = failedStart(dir.path(), "--store mysql://x");
  EXPECT_EQ(storeCode, 1);
  EXPECT_NE(storeOutput.find("--store must be sqlite:PATH or a postgresql:// URI"), std::string::npos)
      << storeOutput;

  auto [tlsCode, tlsOutput] = failedStart(dir.path(), "--tls-cert only.pem");
  EXPECT_EQ(tlsCode, 2);
  EXPECT_NE(tlsOutput.find("--tls-cert and --tls-key go together"), std::string::npos) << tlsOutput;
}

}  // namespace
}  // namespace tessera::test
