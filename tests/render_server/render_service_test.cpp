// RenderService.Render against the real server: frames match gpu::FrameEngine run in this
// process on the same mesh and camera, every format decodes, bad requests are refused with the
// camera and field named, and the server keeps serving afterwards.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "tests/render_server/render_test_support.h"

namespace tessera::test {
namespace {

class RenderTest : public RenderServerTest {};

// The server still renders: a small frame of a good camera comes back complete.
void expectStillServing(v1::RenderService::Stub& stub) {
  RenderCall call = render(stub, renderRequest({framedCamera({0, 0, 1}, 32, 32)}));
  ASSERT_TRUE(call.status.ok()) << call.status.error_message();
  EXPECT_EQ(call.frames.size(), 1u);
}

TEST_F(RenderTest, TwoCamerasGivePngsMatchingTheInProcessEngine) {
  std::vector<tessera::Camera> cameras = {framedCamera({0.3, 0.4, 1}, 128, 128),
                                          framedCamera({-1, 0.2, 0.5}, 128, 96)};
  RenderCall call = render(*renderStub(), renderRequest(cameras));
  ASSERT_TRUE(call.status.ok()) << call.status.error_message();
  ASSERT_EQ(call.frames.size(), 2u);
  for (size_t i = 0; i < cameras.size(); ++i) {
    SCOPED_TRACE("camera " + std::to_string(i));
    const ReceivedFrame& f = call.frames[i];
    EXPECT_EQ(f.header.index(), int(i)) << "frames come in camera order";
    EXPECT_EQ(f.header.format(), v1::IMAGE_FORMAT_PNG);
    EXPECT_EQ(f.header.width(), cameras[i].width);
    EXPECT_EQ(f.header.height(), cameras[i].height);
    EXPECT_GT(f.header.statistics().triangles(), 0);
    EXPECT_GT(f.header.statistics().rings(), 0);
    EXPECT_GE(f.header.statistics().max_ring_depth(), f.header.statistics().average_ring_depth());
    EXPECT_FALSE(f.header.device().empty());

    DecodedImage image = decodeImage(f.bytes, "png");
    ASSERT_EQ(image.width, cameras[i].width);
    ASSERT_EQ(image.height, cameras[i].height);
    ASSERT_EQ(image.channels, 4);
    gpu::EngineFrame reference = referenceFrame(cameras[i]);
    std::vector<bool> served = coverage(image), expected = coverage(reference.frame);
    EXPECT_GT(count(served), served.size() / 10) << "bigguy fills a good part of the view";
    EXPECT_LT(count(served), served.size()) << "and leaves some background";
    EXPECT_GE(intersectionOverUnion(served, expected), 0.999);
    size_t differing = 0;
    for (size_t k = 0; k < image.bytes.size(); ++k)
      differing += image.bytes[k] != reference.frame.rgba[k];
    EXPECT_EQ(differing, 0u) << "PNG is lossless: the served frame is the in-process frame";
    EXPECT_EQ(f.header.statistics().triangles(), int64_t(reference.statistics.triangles));
  }
}

TEST_F(RenderTest, RawRgbaIsTheInProcessFrameByteForByte) {
  // The one large case: 1 MiB of pixels, sent in 16 chunks.
  tessera::Camera camera = framedCamera({0.2, 0.1, 1}, 512, 512);
  RenderCall call = render(*renderStub(), renderRequest({camera}, v1::IMAGE_FORMAT_RAW_RGBA));
  ASSERT_TRUE(call.status.ok()) << call.status.error_message();
  ASSERT_EQ(call.frames.size(), 1u);
  const ReceivedFrame& f = call.frames[0];
  EXPECT_EQ(f.header.format(), v1::IMAGE_FORMAT_RAW_RGBA);
  ASSERT_EQ(f.bytes.size(), 512u * 512u * 4u);
  gpu::EngineFrame reference = referenceFrame(camera);
  ASSERT_EQ(reference.frame.rgba.size(), f.bytes.size());
  EXPECT_TRUE(std::equal(f.bytes.begin(), f.bytes.end(), reference.frame.rgba.begin(),
                         [](char a, uint8_t b) { return uint8_t(a) == b; }));
}

// A mesh far from the origin is stored relative to its centre; a camera in model units sees it
// where it is: bigguy a million units away, seen from the same place relative to it, fills the
// same pixels as bigguy at home.
TEST_F(RenderTest, AMeshFarFromTheOriginIsSeenWhereItIs) {
  const Vec3d far(1e6, -2e6, 5e5);
  const ControlMesh& home = bigguy().mesh;
  std::string obj;
  for (const Vec3& p : home.positions) obj += fmt::format("v {} {} {}\n", p.x + far.x, p.y + far.y, p.z + far.z);
  size_t corner = 0;
  for (int size : home.faceSizes) {
    obj += "f";
    for (int k = 0; k < size; ++k) obj += fmt::format(" {}", home.faceVertices[corner++] + 1);
    obj += "\n";
  }
  auto meshes = v1::MeshService::NewStub(server().channel());
  UploadResult uploaded = uploadMessages(*meshes, objUpload("bigguy-far", obj));
  ASSERT_TRUE(uploaded.status.ok()) << uploaded.status.error_message();
  tessera::Camera camera = framedCamera({0.3, 0.4, 1}, 128, 128);
  tessera::Camera farCamera = camera;
  farCamera.eye = camera.eye + far, farCamera.target = camera.target + far;
  v1::RenderRequest request = renderRequest({farCamera}, v1::IMAGE_FORMAT_RAW_RGBA);
  request.set_name("meshes/bigguy-far");
  RenderCall call = render(*renderStub(), request);
  ASSERT_TRUE(call.status.ok()) << call.status.error_message();
  ASSERT_EQ(call.frames.size(), 1u);
  const ReceivedFrame& f = call.frames[0];
  std::vector<bool> served(f.bytes.size() / 4), expected = coverage(referenceFrame(camera).frame);
  for (size_t i = 0; i < served.size(); ++i) {
    served[i] = f.bytes[4 * i] != 0 || f.bytes[4 * i + 1] != 0 || f.bytes[4 * i + 2] != 0;
  }
  EXPECT_GT(count(served), served.size() / 10);
  EXPECT_GE(intersectionOverUnion(served, expected), 0.99);
}

TEST_F(RenderTest, CameraLookingAwayGivesABackgroundFrame) {
  tessera::Camera camera = framedCamera({0, 0, 1}, 96, 64);
  camera.target = camera.eye + (camera.eye - bigguy().centre);  // turned around
  RenderCall call = render(*renderStub(), renderRequest({camera}, v1::IMAGE_FORMAT_RAW_RGBA));
  ASSERT_TRUE(call.status.ok()) << call.status.error_message();
  ASSERT_EQ(call.frames.size(), 1u);
  const ReceivedFrame& f = call.frames[0];
  EXPECT_EQ(f.header.statistics().triangles(), 0);
  EXPECT_EQ(f.header.statistics().visible_pieces(), 0);
  ASSERT_EQ(f.bytes.size(), 96u * 64u * 4u);
  size_t notBackground = 0;
  for (size_t i = 0; i < f.bytes.size(); i += 4) {
    notBackground += f.bytes[i] != 0 || f.bytes[i + 1] != 0 || f.bytes[i + 2] != 0 ||
                     uint8_t(f.bytes[i + 3]) != 255;
  }
  EXPECT_EQ(notBackground, 0u) << "opaque black everywhere";
}

TEST_F(RenderTest, JpegAndExrDecodeToTheFrame) {
  tessera::Camera camera = framedCamera({0.3, 0.4, 1}, 96, 80);
  gpu::EngineFrame reference = referenceFrame(camera);

  v1::RenderRequest jpeg = renderRequest({camera}, v1::IMAGE_FORMAT_JPEG);
  jpeg.mutable_settings()->set_jpeg_quality(95);
  RenderCall call = render(*renderStub(), jpeg);
  ASSERT_TRUE(call.status.ok()) << call.status.error_message();
  ASSERT_EQ(call.frames.size(), 1u);
  DecodedImage j = decodeImage(call.frames[0].bytes, "jpg");
  ASSERT_EQ(j.width, 96);
  ASSERT_EQ(j.height, 80);
  ASSERT_EQ(j.channels, 3);
  double error = 0;
  for (size_t i = 0; i < size_t(96 * 80); ++i) {
    for (int c = 0; c < 3; ++c)
      error += std::abs(int(j.bytes[3 * i + c]) - int(reference.frame.rgba[4 * i + c]));
  }
  EXPECT_LT(error / (96 * 80 * 3), 4.0) << "mean absolute JPEG error, in 8-bit steps";

  RenderCall exr = render(*renderStub(), renderRequest({camera}, v1::IMAGE_FORMAT_EXR));
  ASSERT_TRUE(exr.status.ok()) << exr.status.error_message();
  ASSERT_EQ(exr.frames.size(), 1u);
  DecodedImage e = decodeImage(exr.frames[0].bytes, "exr");
  ASSERT_EQ(e.width, 96);
  ASSERT_EQ(e.height, 80);
  ASSERT_EQ(e.channels, 5);
  EXPECT_EQ(e.channelNames, (std::vector<std::string>{"R", "G", "B", "A", "Z"}));
  size_t colourOff = 0, depthOff = 0;
  for (size_t i = 0; i < size_t(96 * 80); ++i) {
    for (int c = 0; c < 4; ++c) {
      // Half precision keeps 11 significant bits: far finer than an 8-bit step.
      colourOff += std::abs(e.floats[5 * i + c] - reference.frame.rgba[4 * i + c] / 255.0f) > 1e-3f;
    }
    depthOff += std::abs(e.floats[5 * i + 4] - reference.frame.depth[i]) > 0.0f;
  }
  EXPECT_EQ(colourOff, 0u);
  EXPECT_EQ(depthOff, 0u) << "Z is the frame's window depth, as float";
}

TEST_F(RenderTest, BadCamerasAreRefusedNamingTheCameraAndTheServerKeepsServing) {
  auto stub = renderStub();
  const tessera::Camera good = framedCamera({0, 0, 1}, 64, 64);
  struct Case {
    const char* name;
    void (*spoil)(v1::Camera&);
    std::vector<std::string> words;
  };
  const std::vector<Case> cases = {
      {"NaN eye", [](v1::Camera& c) { c.mutable_eye()->set_x(NAN); }, {"cameras[1].eye", "finite"}},
      {"infinite target",
       [](v1::Camera& c) { c.mutable_target()->set_y(INFINITY); },
       {"cameras[1].target", "finite"}},
      {"zero width", [](v1::Camera& c) { c.set_width(0); }, {"cameras[1].width", "8192"}},
      {"too tall", [](v1::Camera& c) { c.set_height(8193); }, {"cameras[1].height", "8193"}},
      {"eye at target",
       [](v1::Camera& c) { *c.mutable_eye() = c.target(); },
       {"cameras[1]", "eye and target"}},
      {"up along the view",
       [](v1::Camera& c) {
         c.mutable_up()->set_x(c.target().x() - c.eye().x());
         c.mutable_up()->set_y(c.target().y() - c.eye().y());
         c.mutable_up()->set_z(c.target().z() - c.eye().z());
       },
       {"cameras[1].up", "parallel"}},
      {"zero up", [](v1::Camera& c) { *c.mutable_up() = v1::Vec3(); }, {"cameras[1].up"}},
      {"no up", [](v1::Camera& c) { c.clear_up(); }, {"cameras[1].up", "required"}},
      {"fov 0", [](v1::Camera& c) { c.set_fov_y_deg(0); }, {"cameras[1].fov_y_deg"}},
      {"fov 180", [](v1::Camera& c) { c.set_fov_y_deg(180); }, {"cameras[1].fov_y_deg"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    v1::RenderRequest request = renderRequest({good, good});
    c.spoil(*request.mutable_cameras(1));
    RenderCall call = render(*stub, request);
    EXPECT_EQ(call.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    for (const std::string& w : c.words) {
      EXPECT_NE(call.status.error_message().find(w), std::string::npos)
          << "'" << w << "' not in: " << call.status.error_message();
    }
    EXPECT_TRUE(call.frames.empty()) << "cameras are checked before the first frame";
  }
  expectStillServing(*stub);
}

TEST_F(RenderTest, BadRequestsGiveTheStatusTheApiNames) {
  auto stub = renderStub();
  const tessera::Camera good = framedCamera({0, 0, 1}, 64, 64);
  auto expectStatus = [&](v1::RenderRequest request, grpc::StatusCode code,
                          const std::string& word) {
    RenderCall call = render(*stub, request);
    EXPECT_EQ(call.status.error_code(), code) << word << ": " << call.status.error_message();
    EXPECT_NE(call.status.error_message().find(word), std::string::npos)
        << "'" << word << "' not in: " << call.status.error_message();
  };
  v1::RenderRequest r = renderRequest({good});
  r.set_name("meshes/no-such-mesh");
  expectStatus(r, grpc::StatusCode::NOT_FOUND, "no-such-mesh");
  r = renderRequest({good});
  r.set_name("bigguy");
  expectStatus(r, grpc::StatusCode::INVALID_ARGUMENT, "name");
  expectStatus(renderRequest({}), grpc::StatusCode::INVALID_ARGUMENT, "cameras");
  expectStatus(renderRequest(std::vector<tessera::Camera>(65, good)),
               grpc::StatusCode::INVALID_ARGUMENT, "64");
  r = renderRequest({good});
  r.mutable_settings()->set_pixel_accuracy(-1);
  expectStatus(r, grpc::StatusCode::INVALID_ARGUMENT, "settings.pixel_accuracy");
  r = renderRequest({good});
  r.mutable_settings()->set_uniform_level(0);
  expectStatus(r, grpc::StatusCode::INVALID_ARGUMENT, "settings.uniform_level");
  r = renderRequest({good});
  r.mutable_settings()->set_absolute_tolerance(1e6);
  expectStatus(r, grpc::StatusCode::INVALID_ARGUMENT, "settings.absolute_tolerance");
  r = renderRequest({good}, v1::IMAGE_FORMAT_PNG);
  r.mutable_settings()->set_jpeg_quality(80);
  expectStatus(r, grpc::StatusCode::INVALID_ARGUMENT, "jpeg_quality");
  r = renderRequest({good});
  r.mutable_settings()->set_format(static_cast<v1::ImageFormat>(42));
  expectStatus(r, grpc::StatusCode::INVALID_ARGUMENT, "settings.format");
  // A frame over the triangle budget names its camera.
  r = renderRequest({good, good});
  r.mutable_settings()->set_max_triangles(100);
  expectStatus(r, grpc::StatusCode::RESOURCE_EXHAUSTED, "cameras[0]");
  expectStillServing(*stub);
}

TEST_F(RenderTest, OtherModesAndSettingsRender) {
  auto stub = renderStub();
  const tessera::Camera camera = framedCamera({0.3, 0.4, 1}, 64, 64);
  v1::RenderRequest uniform = renderRequest({camera}, v1::IMAGE_FORMAT_RAW_RGBA);
  uniform.mutable_settings()->set_uniform_level(16);
  v1::RenderRequest absolute = renderRequest({camera}, v1::IMAGE_FORMAT_RAW_RGBA);
  absolute.mutable_settings()->set_absolute_tolerance(0.01);
  absolute.mutable_settings()->set_crack_filling(false);
  for (const v1::RenderRequest& request : {uniform, absolute}) {
    RenderCall call = render(*stub, request);
    ASSERT_TRUE(call.status.ok()) << call.status.error_message();
    ASSERT_EQ(call.frames.size(), 1u);
    EXPECT_GT(call.frames[0].header.statistics().triangles(), 0);
  }
  RenderCall noCracks = render(*stub, absolute);
  EXPECT_EQ(noCracks.frames.at(0).header.timings().crack_filling_ms(), 0.0);
}

TEST_F(RenderTest, CancelledCallEndsAndTheServerKeepsServing) {
  auto stub = renderStub();
  v1::RenderRequest request =
      renderRequest(std::vector<tessera::Camera>(8, framedCamera({0, 0, 1}, 64, 64)));
  grpc::ClientContext context;
  prepare(context, {}, 120);
  auto reader = stub->Render(&context, request);
  v1::RenderResponse message;
  ASSERT_TRUE(reader->Read(&message));
  EXPECT_TRUE(message.has_header());
  context.TryCancel();
  while (reader->Read(&message)) {
  }
  EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::CANCELLED);
  expectStillServing(*stub);
}

TEST_F(RenderTest, ServerInfoNamesTheRenderDevice) {
  auto info = v1::ServerInfoService::NewStub(server().channel());
  grpc::ClientContext context;
  prepare(context);
  v1::ServerInfo response;
  ASSERT_TRUE(info->GetServerInfo(&context, {}, &response).ok());
  bool found = false;
  for (const v1::Backend& b : response.backends()) {
    if (b.name() != "vulkan") continue;
    found = true;
    EXPECT_TRUE(b.available()) << b.detail();
  }
  EXPECT_TRUE(found) << "a vulkan backend is listed";
  EXPECT_NE(response.device().find("render device: "), std::string::npos) << response.device();
  // The device that drew a frame is the one named.
  RenderCall call = render(*renderStub(), renderRequest({framedCamera({0, 0, 1}, 32, 32)}));
  ASSERT_EQ(call.frames.size(), 1u);
  EXPECT_NE(response.device().find(call.frames[0].header.device()), std::string::npos);
}

}  // namespace
}  // namespace tessera::test
