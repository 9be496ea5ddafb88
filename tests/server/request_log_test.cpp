// The request log: one line per call with its id, method, status, duration and peer, and what the
// handler learned (the mesh, the triangles and bytes it sent), as text by default and as one JSON
// object a line with --log-format json, checked against what the client itself received.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

// The log line of the only call to `method`; every line of a JSON log must be an object with a
// time and a level.
nlohmann::json jsonLineOf(const std::string& log, const std::string& method) {
  nlohmann::json found;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    const nlohmann::json parsed = nlohmann::json::parse(line, nullptr, false);
    EXPECT_TRUE(parsed.is_object() && parsed.contains("time") && parsed.contains("level")) << line;
    if (parsed.is_object() && parsed.value("method", "") == method) {
      EXPECT_TRUE(found.is_null()) << "two lines for " << method;
      found = parsed;
    }
  }
  return found;
}

struct Logged {
  std::unique_ptr<ServerProcess> server;
  int64_t uploadedBytes = 0;
  Streamed tessellated;
};

// An upload and a tessellation of a small grid on a server started with `flags`.
Logged uploadAndTessellate(const TempDir& dir, std::vector<std::string> flags) {
  flags.insert(flags.end(), {"--store", "sqlite:" + (dir.path() / "m.db").string()});
  Logged run;
  run.server = ServerProcess::start(dir.path(), flags);
  if (!run.server) return run;
  auto meshes = v1::MeshService::NewStub(run.server->channel());
  const MeshArrays mesh = gridMesh(4, 0);
  run.uploadedBytes = mesh.uploadBytes();
  EXPECT_TRUE(uploadMessages(*meshes, arraysUpload("logged", mesh)).status.ok());
  auto tessellation = v1::TessellationService::NewStub(run.server->channel());
  v1::TessellateRequest request;
  request.set_name("meshes/logged");
  request.set_relative(1e-3);
  run.tessellated = tessellateOverGrpc(*tessellation, request);
  EXPECT_TRUE(run.tessellated.status.ok() && run.tessellated.problem.empty())
      << run.tessellated.problem;
  return run;
}

TEST(RequestLog, JsonLinesCarryTheCallsFieldsAndWhatItSent) {
  TempDir dir;
  Logged run = uploadAndTessellate(dir, {"--log-format", "json"});
  ASSERT_TRUE(run.server && run.tessellated.summary);
  const std::string log = run.server->log();

  const nlohmann::json upload = jsonLineOf(log, "/tessera.v1.MeshService/UploadMesh");
  ASSERT_TRUE(upload.is_object()) << log;
  EXPECT_EQ(upload["status"], "OK");
  EXPECT_EQ(upload["mesh"], "logged");
  EXPECT_EQ(upload["bytes"], run.uploadedBytes);
  EXPECT_FALSE(upload["request_id"].get<std::string>().empty());

  const nlohmann::json tessellate = jsonLineOf(log, "/tessera.v1.TessellationService/Tessellate");
  ASSERT_TRUE(tessellate.is_object()) << log;
  EXPECT_EQ(tessellate["status"], "OK");
  EXPECT_EQ(tessellate["mesh"], "logged");
  EXPECT_EQ(tessellate["triangles"], run.tessellated.summary->triangles());
  EXPECT_EQ(tessellate["bytes"], int64_t(run.tessellated.glb.size()));
  EXPECT_TRUE(tessellate["duration_ms"].is_number() && tessellate["duration_ms"].get<double>() > 0);
  EXPECT_NE(tessellate["request_id"], upload["request_id"]);
}

TEST(RequestLog, TextLinesCarryTheSameFields) {
  TempDir dir;
  Logged run = uploadAndTessellate(dir, {});
  ASSERT_TRUE(run.server && run.tessellated.summary);
  const std::string log = run.server->log();
  const std::string expected =
      "method=/tessera.v1.TessellationService/Tessellate status=OK duration_ms=";
  const size_t at = log.find(expected);
  ASSERT_NE(at, std::string::npos) << log;
  const std::string line = log.substr(at, log.find('\n', at) - at);
  EXPECT_NE(
      line.find(" mesh=logged triangles=" + std::to_string(run.tessellated.summary->triangles()) +
                " bytes=" + std::to_string(run.tessellated.glb.size())),
      std::string::npos)
      << line;
}

}  // namespace
}  // namespace tessera::test
