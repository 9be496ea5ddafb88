// RenderService.RenderSession against the real server: a client that sends cameras faster than
// frames come back sees stale cameras dropped (sequence numbers skip, never go back) and always
// gets the last one; failures of one frame are reported in-band; malformed sessions end with
// INVALID_ARGUMENT naming the update.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "tests/render_server/render_test_support.h"

namespace tessera::test {
namespace {

using Session = grpc::ClientReaderWriter<v1::SessionRequest, v1::SessionResponse>;

class RenderSessionTest : public RenderServerTest {
 protected:
  void SetUp() override {
    stub_ = renderStub();
    prepare(context_, {}, 120);
    session_ = stub_->RenderSession(&context_);
  }

  void start(v1::RenderSettings settings = {}) {
    v1::SessionRequest message;
    message.mutable_start()->set_name("meshes/bigguy");
    *message.mutable_start()->mutable_settings() = settings;
    ASSERT_TRUE(session_->Write(message));
  }

  bool sendCamera(const tessera::Camera& camera, uint64_t sequence = 0) {
    v1::SessionRequest message;
    *message.mutable_camera()->mutable_camera() = toProto(camera);
    message.mutable_camera()->set_sequence(sequence);
    return session_->Write(message);
  }

  // The next complete frame or frame error; false at the end of the stream.
  struct Event {
    bool isFrame = false;
    ReceivedFrame frame;
    v1::FrameError error;
  };
  bool next(Event& event) {
    v1::SessionResponse message;
    while (session_->Read(&message)) {
      if (message.has_error()) {
        EXPECT_FALSE(frames_.inFrame()) << "an error arrived inside a frame";
        event = {false, {}, message.error()};
        return true;
      }
      if (frames_.add(message.has_header() ? &message.header() : nullptr,
                      message.has_chunk() ? &message.chunk() : nullptr)) {
        event = {true, frames_.last(), {}};
        return true;
      }
    }
    return false;
  }

  std::unique_ptr<v1::RenderService::Stub> stub_;
  grpc::ClientContext context_;
  std::unique_ptr<Session> session_;
  FrameAssembler frames_;
};

// 20 cameras on a circle around bigguy, small enough to keep the test quick.
std::vector<tessera::Camera> orbit(int count) {
  std::vector<tessera::Camera> cameras;
  for (int i = 0; i < count; ++i) {
    double angle = 2 * M_PI * i / count;
    cameras.push_back(framedCamera({std::sin(angle), 0.3, std::cos(angle)}, 96, 96));
  }
  return cameras;
}

TEST_F(RenderSessionTest, StaleCamerasAreDroppedAndTheLastIsAlwaysRendered) {
  v1::RenderSettings settings;
  settings.set_format(v1::IMAGE_FORMAT_PNG);
  start(settings);
  const std::vector<tessera::Camera> cameras = orbit(20);
  // All at once: drawing a frame takes far longer than sending a camera, so most of these
  // arrive while the first frame is being drawn and replace one another.
  for (const tessera::Camera& camera : cameras) ASSERT_TRUE(sendCamera(camera));
  ASSERT_TRUE(session_->WritesDone());

  std::vector<uint64_t> sequences;
  Event event;
  while (next(event)) {
    ASSERT_TRUE(event.isFrame) << "frame error " << event.error.code() << ": "
                               << event.error.message();
    const v1::FrameHeader& h = event.frame.header;
    ASSERT_GE(h.sequence(), 1u);
    ASSERT_LE(h.sequence(), 20u);
    if (!sequences.empty()) {
      EXPECT_GT(h.sequence(), sequences.back()) << "never back in time";
    }
    sequences.push_back(h.sequence());
    // The frame shows the camera of its sequence number.
    DecodedImage image = decodeImage(event.frame.bytes, "png");
    gpu::EngineFrame reference = referenceFrame(cameras[h.sequence() - 1]);
    EXPECT_GE(intersectionOverUnion(coverage(image), coverage(reference.frame)), 0.999)
        << "frame " << h.sequence();
    // A slow reader: the server keeps drawing the newest camera meanwhile.
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  grpc::Status status = session_->Finish();
  ASSERT_TRUE(status.ok()) << status.error_message();
  std::string drawn;
  for (uint64_t s : sequences) {
    if (!drawn.empty()) drawn += ' ';
    drawn += std::to_string(s);
  }
  RecordProperty("drawn_sequences", drawn);
  ASSERT_FALSE(sequences.empty());
  EXPECT_EQ(sequences.back(), 20u) << "the last camera is always drawn";
  EXPECT_LT(sequences.size(), 20u) << "stale cameras are dropped";
}

TEST_F(RenderSessionTest, ExplicitSequenceNumbersAreEchoed) {
  start();
  const std::vector<tessera::Camera> cameras = orbit(3);
  Event event;
  for (uint64_t i = 0; i < 3; ++i) {
    // One at a time, so none is dropped.
    ASSERT_TRUE(sendCamera(cameras[i], 10 * (i + 1)));
    ASSERT_TRUE(next(event));
    ASSERT_TRUE(event.isFrame) << event.error.message();
    EXPECT_EQ(event.frame.header.sequence(), 10 * (i + 1));
    EXPECT_EQ(event.frame.header.width(), 96);
  }
  ASSERT_TRUE(session_->WritesDone());
  EXPECT_FALSE(next(event));
  EXPECT_TRUE(session_->Finish().ok());
}

TEST_F(RenderSessionTest, AFrameThatFailsIsReportedAndTheSessionGoesOn) {
  v1::RenderSettings settings;
  settings.set_max_triangles(1000);  // bigguy in view needs far more
  start(settings);
  tessera::Camera facing = framedCamera({0, 0, 1}, 64, 64);
  tessera::Camera away = facing;
  away.target = away.eye + (away.eye - bigguy().centre);
  Event event;
  ASSERT_TRUE(sendCamera(facing));
  ASSERT_TRUE(next(event));
  ASSERT_FALSE(event.isFrame);
  EXPECT_EQ(event.error.sequence(), 1u);
  EXPECT_EQ(event.error.code(), int(grpc::StatusCode::RESOURCE_EXHAUSTED));
  EXPECT_NE(event.error.message().find("triangles"), std::string::npos) << event.error.message();
  ASSERT_TRUE(sendCamera(away));
  ASSERT_TRUE(next(event));
  ASSERT_TRUE(event.isFrame) << event.error.message();
  EXPECT_EQ(event.frame.header.sequence(), 2u);
  ASSERT_TRUE(session_->WritesDone());
  EXPECT_TRUE(session_->Finish().ok());
}

TEST_F(RenderSessionTest, ABadCameraEndsTheSessionNamingIt) {
  start();
  Event event;
  ASSERT_TRUE(sendCamera(framedCamera({0, 0, 1}, 64, 64)));
  ASSERT_TRUE(next(event));
  tessera::Camera bad = framedCamera({0, 0, 1}, 64, 64);
  bad.width = 0;
  sendCamera(bad);
  while (next(event)) {
  }
  grpc::Status status = session_->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("camera[sequence 2].width"), std::string::npos)
      << status.error_message();
}

TEST_F(RenderSessionTest, SequenceNumbersMustIncrease) {
  start();
  Event event;
  ASSERT_TRUE(sendCamera(framedCamera({0, 0, 1}, 32, 32), 5));
  ASSERT_TRUE(next(event));
  sendCamera(framedCamera({0, 0, 1}, 32, 32), 5);
  while (next(event)) {
  }
  grpc::Status status = session_->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("sequence"), std::string::npos) << status.error_message();
}

TEST_F(RenderSessionTest, TheFirstMessageMustStartTheSession) {
  ASSERT_TRUE(sendCamera(framedCamera({0, 0, 1}, 32, 32)));
  session_->WritesDone();
  Event event;
  EXPECT_FALSE(next(event));
  grpc::Status status = session_->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("SessionStart"), std::string::npos)
      << status.error_message();
}

TEST_F(RenderSessionTest, AnUnknownMeshIsNotFound) {
  v1::SessionRequest message;
  message.mutable_start()->set_name("meshes/missing");
  ASSERT_TRUE(session_->Write(message));
  session_->WritesDone();
  Event event;
  EXPECT_FALSE(next(event));
  EXPECT_EQ(session_->Finish().error_code(), grpc::StatusCode::NOT_FOUND);
}

TEST_F(RenderSessionTest, AClientThatHangsUpLeavesTheServerServing) {
  start();
  Event event;
  ASSERT_TRUE(sendCamera(framedCamera({0, 0, 1}, 64, 64)));
  ASSERT_TRUE(next(event));
  for (const tessera::Camera& camera : orbit(5)) sendCamera(camera);
  context_.TryCancel();
  while (next(event)) {
  }
  EXPECT_EQ(session_->Finish().error_code(), grpc::StatusCode::CANCELLED);
  RenderCall call = render(*renderStub(), renderRequest({framedCamera({0, 0, 1}, 32, 32)}));
  EXPECT_TRUE(call.status.ok()) << call.status.error_message();
}

}  // namespace
}  // namespace tessera::test
