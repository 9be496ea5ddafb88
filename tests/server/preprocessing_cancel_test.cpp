// Preprocessing (OpenSubdiv's topology, rings, the surface tree) is the longest stage of a first
// request for a mesh and grows with its largest valence; a deadline or cancellation must stop it,
// not leave it running for the rest of the minute while the call is long gone.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <thread>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

// A disc of n triangles round one vertex: preprocessing it takes ~20 s on two cores at n = 16,000,
// and its patch set ~0.6 GB (the cache below is large enough to keep it, had it been finished).
std::string fanObj(int n) {
  std::ostringstream obj;
  obj << "v 0 0 0.3\n";
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    obj << "v " << std::cos(a) << ' ' << std::sin(a) << " 0\n";
  }
  for (int i = 0; i < n; ++i) obj << "f 1 " << i + 2 << ' ' << (i + 1) % n + 2 << '\n';
  return obj.str();
}

TEST(PreprocessingCancel, ADeadlineStopsPreprocessingAndFreesTheSlot) {
  TempDir dir;
  auto server = ServerProcess::start(
      dir.path(), {"--max-concurrent-jobs", "1", "--max-queued-jobs", "0", "--patch-cache-bytes", "2GiB"});
  ASSERT_TRUE(server);
  auto meshes = v1::MeshService::NewStub(server->channel());
  ASSERT_TRUE(uploadMessages(*meshes, arraysUpload("fan", parseObjVerticesAndFaces(fanObj(16000)))).status.ok());

  auto tessellation = v1::TessellationService::NewStub(server->channel());
  grpc::ClientContext context;
  prepare(context, {}, 2);
  v1::TessellateRequest request;
  request.set_name("meshes/fan");
  request.set_relative(0.01);
  auto reader = tessellation->Tessellate(&context, request);
  v1::TessellateResponse message;
  while (reader->Read(&message)) {
  }
  EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::DEADLINE_EXCEEDED);

  // The job slot comes back (an upload needs it, and nothing may queue); then the fan's patch
  // set must not be in the cache: its preprocessing was abandoned, not finished unseen.
  grpc::Status upload;
  for (int attempt = 0; attempt < 600; ++attempt) {
    upload = uploadMessages(*meshes, arraysUpload("probe-" + std::to_string(attempt), gridMesh(2, 0))).status;
    if (upload.error_code() != grpc::StatusCode::RESOURCE_EXHAUSTED) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(upload.ok()) << upload.error_message();
  const std::string metrics = httpGet(server->metricsAddress(), "/metrics");
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_misses_total"), 1);
  EXPECT_EQ(seriesValue(metrics, "tessera_patch_cache_bytes"), 0);
}

}  // namespace
}  // namespace tessera::test
