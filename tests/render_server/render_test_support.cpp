#include "tests/render_server/render_test_support.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdlib>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"

namespace tessera::test {

std::unique_ptr<TempDir> RenderServerTest::dir_;
std::unique_ptr<ServerProcess> RenderServerTest::server_;

const ReferenceModel& bigguy() {
  static const ReferenceModel model = [] {
    ReferenceModel m;
    m.mesh = readObjFile(modelPath("bigguy.obj").string());
    m.patches = buildPatchSet(m.mesh);
    Vec3d lo(m.patches.boundsMin), hi(m.patches.boundsMax);
    m.centre = (lo + hi) * 0.5;
    m.radius = 0.5 * length(hi - lo);
    return m;
  }();
  return model;
}

gpu::FrameEngine& referenceEngine() {
  static gpu::FrameEngine engine =
      gpu::FrameEngine::create(gpu::DeviceSelection::fromEnvironment());
  return engine;
}

gpu::EngineFrame referenceFrame(const tessera::Camera& camera) {
  gpu::FrameRequest request;
  request.camera = camera;
  request.accuracy = Accuracy::pixel(0.5);
  request.render.crackFilling = true;
  return referenceEngine().render(bigguy().patches, request);
}

tessera::Camera framedCamera(Vec3d direction, int width, int height, double fovYDegrees) {
  const ReferenceModel& model = bigguy();
  double halfY = fovYDegrees * M_PI / 360.0;
  double halfX = std::atan(std::tan(halfY) * width / height);
  double distance = 1.05 * model.radius / std::sin(std::min(halfX, halfY));
  tessera::Camera camera;
  camera.target = model.centre;
  camera.eye = model.centre + direction * (distance / length(direction));
  camera.up = Vec3d(0, 1, 0);
  camera.fovYDegrees = fovYDegrees;
  camera.width = width;
  camera.height = height;
  return camera;
}

v1::Camera toProto(const tessera::Camera& c) {
  v1::Camera out;
  auto set = [](v1::Vec3* v, const Vec3d& from) {
    v->set_x(from.x);
    v->set_y(from.y);
    v->set_z(from.z);
  };
  set(out.mutable_eye(), c.eye);
  set(out.mutable_target(), c.target);
  set(out.mutable_up(), c.up);
  out.set_fov_y_deg(c.fovYDegrees);
  out.set_width(c.width);
  out.set_height(c.height);
  return out;
}

void RenderServerTest::SetUpTestSuite() {
  dir_ = std::make_unique<TempDir>();
  std::map<std::string, std::string> env;
  if (const char* device = std::getenv("TESSERA_VK_DEVICE")) env["TESSERA_VK_DEVICE"] = device;
  server_ = ServerProcess::start(dir_->path(),
                                 {"--store", "sqlite:" + (dir_->path() / "t.db").string()}, env);
  ASSERT_TRUE(server_) << "tessera-server did not start";
  auto meshes = v1::MeshService::NewStub(server_->channel());
  UploadResult upload =
      uploadModel(*meshes, "bigguy");
  ASSERT_TRUE(upload.status.ok()) << upload.status.error_message();
}

void RenderServerTest::TearDownTestSuite() {
  server_.reset();
  dir_.reset();
}

ServerProcess& RenderServerTest::server() {
  if (!server_) throw std::runtime_error("the test server did not start");
  return *server_;
}

std::unique_ptr<v1::RenderService::Stub> RenderServerTest::renderStub() {
  return v1::RenderService::NewStub(server().channel());
}

bool FrameAssembler::add(const v1::FrameHeader* header, const v1::ImageChunk* chunk) {
  if (header) {
    EXPECT_FALSE(open_) << "a header arrived before the previous frame was complete";
    frames_.push_back({*header, {}});
    open_ = true;
  } else if (chunk) {
    EXPECT_TRUE(open_) << "a chunk arrived outside a frame";
    if (!open_) return false;
    ReceivedFrame& f = frames_.back();
    EXPECT_EQ(chunk->offset(), int64_t(f.bytes.size())) << "chunk offsets must be contiguous";
    EXPECT_LE(chunk->data().size(), 64u * 1024u) << "chunks are at most 64 KiB";
    f.bytes += chunk->data();
  }
  if (!open_) return false;
  ReceivedFrame& f = frames_.back();
  if (int64_t(f.bytes.size()) < f.header.image_bytes()) return false;
  EXPECT_EQ(int64_t(f.bytes.size()), f.header.image_bytes());
  EXPECT_EQ(sha256Hex(f.bytes), f.header.image_sha256());
  open_ = false;
  return true;
}

RenderCall render(v1::RenderService::Stub& stub, const v1::RenderRequest& request,
                  int deadlineSeconds) {
  grpc::ClientContext context;
  prepare(context, {}, deadlineSeconds);
  auto reader = stub.Render(&context, request);
  FrameAssembler frames;
  v1::RenderResponse message;
  while (reader->Read(&message)) {
    frames.add(message.has_header() ? &message.header() : nullptr,
               message.has_chunk() ? &message.chunk() : nullptr);
  }
  RenderCall call;
  call.status = reader->Finish();
  EXPECT_FALSE(frames.inFrame() && call.status.ok()) << "the call ended inside a frame";
  call.frames = frames.frames();
  return call;
}

v1::RenderRequest renderRequest(const std::vector<tessera::Camera>& cameras,
                                v1::ImageFormat format) {
  v1::RenderRequest request;
  request.set_name("meshes/bigguy");
  for (const tessera::Camera& c : cameras) *request.add_cameras() = toProto(c);
  request.mutable_settings()->set_format(format);
  return request;
}

namespace {

DecodedImage decode(OIIO::ImageInput& input) {
  const OIIO::ImageSpec& spec = input.spec();
  DecodedImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels;
  for (const std::string& name : spec.channelnames) image.channelNames.push_back(name);
  size_t values = size_t(spec.width) * spec.height * spec.nchannels;
  image.bytes.resize(values);
  image.floats.resize(values);
  EXPECT_TRUE(input.read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, image.bytes.data()))
      << input.geterror();
  EXPECT_TRUE(input.read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.floats.data()))
      << input.geterror();
  return image;
}

}  // namespace

DecodedImage decodeImage(const std::string& encoded, const std::string& formatHint) {
  OIIO::Filesystem::IOMemReader memory(encoded.data(), encoded.size());
  void* proxy = &memory;
  OIIO::ImageSpec config;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  std::string name = "frame." + formatHint;
  auto input = OIIO::ImageInput::open(name, &config);
  if (!input) {
    ADD_FAILURE() << "cannot decode the " << formatHint << " image: " << OIIO::geterror();
    return {};
  }
  return decode(*input);
}

DecodedImage decodeImageFile(const std::string& path) {
  auto input = OIIO::ImageInput::open(path);
  if (!input) {
    ADD_FAILURE() << "cannot decode " << path << ": " << OIIO::geterror();
    return {};
  }
  return decode(*input);
}

std::vector<bool> coverage(const gpu::Frame& frame) {
  std::vector<bool> mask(size_t(frame.width) * frame.height);
  for (size_t i = 0; i < mask.size(); ++i) {
    mask[i] = frame.rgba[4 * i] != 0 || frame.rgba[4 * i + 1] != 0 || frame.rgba[4 * i + 2] != 0;
  }
  return mask;
}

std::vector<bool> coverage(const DecodedImage& image) {
  std::vector<bool> mask(size_t(image.width) * image.height);
  for (size_t i = 0; i < mask.size(); ++i) {
    for (int c = 0; c < std::min(image.channels, 3); ++c) {
      if (image.bytes[i * image.channels + c] != 0) mask[i] = true;
    }
  }
  return mask;
}

double intersectionOverUnion(const std::vector<bool>& a, const std::vector<bool>& b) {
  EXPECT_EQ(a.size(), b.size());
  size_t both = 0, either = 0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    both += a[i] && b[i];
    either += a[i] || b[i];
  }
  return either == 0 ? 1.0 : double(both) / double(either);
}

size_t count(const std::vector<bool>& mask) {
  size_t n = 0;
  for (bool m : mask) n += m;
  return n;
}

}  // namespace tessera::test
