// TessellationService around the engine: admission and its retry hint, cancellation and
// deadlines reaching a running job, and the GLB stream (chunk sizes, offsets, checksum). Uses the
// server's test engines (--test-engine), which hold a job until cancelled or return a fixed byte
// pattern, so these behaviours are tested apart from real tessellation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <thread>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

// Must match server/tessellation/test_engines.h: the pattern engine's output.
constexpr size_t kPatternBytes = 200'003;
uint8_t patternByte(size_t i) { return static_cast<uint8_t>((i * 131 + (i >> 8)) & 0xff); }

constexpr size_t kMaxChunkBytes = 64 * 1024;

class TessellationServiceTest : public ::testing::Test {
 protected:
  void startServer(const std::string& engine, std::vector<std::string> flags = {}) {
    flags.insert(flags.end(), {"--store", "sqlite:" + (dir_.path() / "m.db").string(),
                               "--test-engine", engine});
    server_ = ServerProcess::start(dir_.path(), flags);
    ASSERT_TRUE(server_);
    auto meshes = v1::MeshService::NewStub(server_->channel());
    ASSERT_TRUE(uploadMessages(*meshes, arraysUpload("grid", gridMesh(4, 0))).status.ok());
  }

  static v1::TessellateRequest request() {
    v1::TessellateRequest r;
    r.set_name("meshes/grid");
    r.set_relative(0.001);
    return r;
  }

  // A call whose stream the test reads message by message.
  struct Call {
    grpc::ClientContext context;
    std::unique_ptr<grpc::ClientReader<v1::TessellateResponse>> reader;
  };
  std::unique_ptr<Call> startCall(int deadlineSeconds = 60) {
    auto call = std::make_unique<Call>();
    prepare(call->context, {}, deadlineSeconds);
    call->reader = stub()->Tessellate(&call->context, request());
    return call;
  }
  // Reads until a progress message with this stage arrives; false if the stream ends first.
  static bool readUntilStage(Call& call, const std::string& stage) {
    v1::TessellateResponse message;
    while (call.reader->Read(&message)) {
      if (message.has_progress() && message.progress().stage() == stage) return true;
    }
    return false;
  }
  std::unique_ptr<v1::TessellationService::Stub> stub() {
    return v1::TessellationService::NewStub(server_->channel());
  }

  TempDir dir_;
  std::unique_ptr<ServerProcess> server_;
};

TEST_F(TessellationServiceTest, TheResultStreamsInChunksOfAtMost64KiBWithAMatchingChecksum) {
  startServer("pattern");
  grpc::ClientContext context;
  prepare(context);
  auto reader = stub()->Tessellate(&context, request());
  std::string glb;
  std::vector<int64_t> offsets;
  std::optional<v1::TessellationSummary> summary;
  bool chunkAfterSummary = false;
  v1::TessellateResponse message;
  while (reader->Read(&message)) {
    if (message.has_glb_chunk()) {
      chunkAfterSummary |= summary.has_value();
      offsets.push_back(message.glb_chunk().offset());
      EXPECT_LE(message.glb_chunk().data().size(), kMaxChunkBytes);
      glb += message.glb_chunk().data();
    } else if (message.has_summary()) {
      summary = message.summary();
    }
  }
  ASSERT_TRUE(reader->Finish().ok());

  ASSERT_TRUE(summary);
  EXPECT_FALSE(chunkAfterSummary);
  ASSERT_EQ(glb.size(), kPatternBytes);
  for (size_t i = 0; i < glb.size(); ++i) {
    ASSERT_EQ(static_cast<uint8_t>(glb[i]), patternByte(i)) << "byte " << i;
  }
  EXPECT_EQ(offsets, (std::vector<int64_t>{0, 65536, 131072, 196608}));
  EXPECT_EQ(summary->glb_size(), static_cast<int64_t>(kPatternBytes));
  EXPECT_EQ(summary->glb_sha256(), sha256Hex(glb));
  // 0.001 of the grid's bounding-box diagonal is the absolute tolerance the job ran with.
  MeshArrays grid = gridMesh(4, 0);
  double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
  for (size_t i = 0; i < grid.positions.size(); ++i) {
    lo[i % 3] = std::min<double>(lo[i % 3], grid.positions[i]);
    hi[i % 3] = std::max<double>(hi[i % 3], grid.positions[i]);
  }
  double diagonal = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  EXPECT_NEAR(summary->tolerance(), 0.001 * diagonal, 1e-12);
}

TEST_F(TessellationServiceTest, AFullQueueIsRefusedWithARetryHint) {
  startServer("block", {"--max-concurrent-jobs", "1", "--max-queued-jobs", "1"});
  auto running = startCall();
  ASSERT_TRUE(readUntilStage(*running, "test-blocking"));  // holds the only slot
  auto queued = startCall();
  ASSERT_TRUE(readUntilStage(*queued, "queued"));  // holds the only queue place

  grpc::ClientContext context;
  prepare(context);
  auto reader = stub()->Tessellate(&context, request());
  v1::TessellateResponse message;
  while (reader->Read(&message)) {
  }
  grpc::Status refused = reader->Finish();

  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(refused.error_message().find("server busy"), std::string::npos);
  EXPECT_NE(refused.error_message().find("retry after"), std::string::npos);
  const auto& trailers = context.GetServerTrailingMetadata();
  auto pushback = trailers.find("grpc-retry-pushback-ms");
  ASSERT_NE(pushback, trailers.end());
  EXPECT_GT(std::stoi(std::string(pushback->second.data(), pushback->second.size())), 0);

  running->context.TryCancel();
  queued->context.TryCancel();
  EXPECT_EQ(running->reader->Finish().error_code(), grpc::StatusCode::CANCELLED);
  EXPECT_EQ(queued->reader->Finish().error_code(), grpc::StatusCode::CANCELLED);
}

TEST_F(TessellationServiceTest, CancellingARunningJobFreesItsSlotForTheNext) {
  startServer("block", {"--max-concurrent-jobs", "1", "--max-queued-jobs", "1"});
  auto first = startCall();
  ASSERT_TRUE(readUntilStage(*first, "test-blocking"));
  auto second = startCall();
  ASSERT_TRUE(readUntilStage(*second, "queued"));

  first->context.TryCancel();

  // The queued job starts only because the cancelled one let go of the slot.
  EXPECT_TRUE(readUntilStage(*second, "test-blocking"));
  second->context.TryCancel();
  EXPECT_EQ(first->reader->Finish().error_code(), grpc::StatusCode::CANCELLED);
  second->reader->Finish();
}

TEST_F(TessellationServiceTest, ADeadlineEndsARunningJobAndFreesItsSlot) {
  startServer("block", {"--max-concurrent-jobs", "1", "--max-queued-jobs", "0"});
  // Long enough for a loaded CI machine to start the job before the deadline.
  auto call = startCall(3);
  EXPECT_TRUE(readUntilStage(*call, "test-blocking"));
  grpc::Status status = call->reader->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED);
  // Whichever side ends the call first, client or server, the message says so.
  EXPECT_NE(status.error_message().find("Deadline Exceeded"), std::string::npos)
      << status.error_message();

  // With no queue, a new job is admitted only once the expired one has left; the server notices
  // the deadline by itself, so retry until it has (bounded, no timing asserted).
  grpc::Status next;
  for (int attempt = 0; attempt < 200; ++attempt) {
    auto retry = startCall();
    if (readUntilStage(*retry, "test-blocking")) {
      retry->context.TryCancel();
      next = retry->reader->Finish();
      break;
    }
    next = retry->reader->Finish();
    ASSERT_EQ(next.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << next.error_message();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_EQ(next.error_code(), grpc::StatusCode::CANCELLED);
}

TEST_F(TessellationServiceTest, ServerInfoDescribesTheEngineAndLimits) {
  startServer("pattern", {"--max-triangles", "12345", "--max-concurrent-jobs", "3"});
  auto info = v1::ServerInfoService::NewStub(server_->channel());
  grpc::ClientContext context;
  prepare(context);
  v1::ServerInfo response;
  ASSERT_TRUE(info->GetServerInfo(&context, {}, &response).ok());
  EXPECT_EQ(response.version(), "0.1.0");
  EXPECT_EQ(response.store(), "sqlite");
  EXPECT_FALSE(response.auth_required());
  EXPECT_EQ(response.limits().max_triangles(), 12345);
  EXPECT_EQ(response.limits().max_concurrent_jobs(), 3);
  EXPECT_EQ(response.limits().max_queued_jobs(), 96);  // 32 per running job by default
  // The tessellation engine comes first; a renderer, when built, is listed after it.
  ASSERT_GE(response.backends_size(), 1);
  EXPECT_EQ(response.backends(0).name(), "test-pattern");
}

}  // namespace
}  // namespace tessera::test
