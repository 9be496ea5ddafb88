// What the RenderService tests share: a real tessera-server with bigguy uploaded, the same mesh
// rendered in this process by gpu::FrameEngine (the reference a served frame must match),
// cameras framed on it, raw Render calls whose frames are reassembled and checked against the
// stream's promises, and image decoding through OpenImageIO.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"
#include "gpu/render_engine/frame_engine.h"
#include "tessera/v1/render.grpc.pb.h"
#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {

// bigguy, read and reduced to patches in this process.
struct ReferenceModel {
  ControlMesh mesh;
  PatchSet patches;
  Vec3d centre;
  double radius = 0;  // of the bounding box's sphere
};
const ReferenceModel& bigguy();

// FrameEngine on the device the selection finds (TESSERA_VK_DEVICE, as the server's).
gpu::FrameEngine& referenceEngine();

// The in-process frame for a camera with the server's defaults (pixel accuracy 0.5, crack
// filling on, black background).
gpu::EngineFrame referenceFrame(const tessera::Camera& camera);

// A camera looking at bigguy's centre from `direction`, far enough for it to fill the view.
tessera::Camera framedCamera(Vec3d direction, int width, int height, double fovYDegrees = 40);
v1::Camera toProto(const tessera::Camera& camera);

// A server with bigguy uploaded as meshes/bigguy, started once per test suite and stopped after
// it; the server's environment gets TESSERA_VK_DEVICE when this process has it.
class RenderServerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite();
  static void TearDownTestSuite();
  static ServerProcess& server();
  static std::unique_ptr<v1::RenderService::Stub> renderStub();

 private:
  static std::unique_ptr<TempDir> dir_;
  static std::unique_ptr<ServerProcess> server_;
};

struct ReceivedFrame {
  v1::FrameHeader header;
  std::string bytes;
};

// A Render call read to the end. Every frame's chunks are checked as they arrive (contiguous
// offsets, at most 64 KiB, total and SHA-256 as the header says); a violation fails the test.
struct RenderCall {
  grpc::Status status;
  std::vector<ReceivedFrame> frames;
};
RenderCall render(v1::RenderService::Stub& stub, const v1::RenderRequest& request,
                  int deadlineSeconds = 120);

// Reassembles frames from a stream of headers and chunks, checking them as render() does.
class FrameAssembler {
 public:
  // Returns true when message completed a frame (then available as last()).
  bool add(const v1::FrameHeader* header, const v1::ImageChunk* chunk);
  const ReceivedFrame& last() const { return frames_.back(); }
  const std::vector<ReceivedFrame>& frames() const { return frames_; }
  bool inFrame() const { return open_; }

 private:
  std::vector<ReceivedFrame> frames_;
  bool open_ = false;
};

v1::RenderRequest renderRequest(const std::vector<tessera::Camera>& cameras,
                                v1::ImageFormat format = v1::IMAGE_FORMAT_PNG);

// An image decoded by OpenImageIO, as 8-bit or float channels.
struct DecodedImage {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<std::string> channelNames;
  std::vector<uint8_t> bytes;  // decoded as UINT8
  std::vector<float> floats;   // decoded as FLOAT
};
DecodedImage decodeImage(const std::string& encoded, const std::string& formatHint);
DecodedImage decodeImageFile(const std::string& path);

// Covered pixels: where a frame's colour differs from the black background (crack filling
// colours pixels between pieces without giving them a patch id, so colour is the silhouette).
std::vector<bool> coverage(const gpu::Frame& frame);
std::vector<bool> coverage(const DecodedImage& image);
double intersectionOverUnion(const std::vector<bool>& a, const std::vector<bool>& b);
size_t count(const std::vector<bool>& mask);

}  // namespace tessera::test
