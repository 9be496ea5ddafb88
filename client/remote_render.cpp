#include "client/remote_render.h"

#include <fmt/format.h>
#include <openssl/evp.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <regex>
#include <stdexcept>

#include "client/remote_progress.h"
#include "client/remote_staged_output.h"
#include "core/request/camera_text.h"
#include "tessera/v1/render.grpc.pb.h"

namespace tessera::cli {
namespace {

namespace v1 = tessera::v1;

// The server's limit on cameras per Render call (render.proto); a longer turntable is sent as
// several calls.
constexpr int kCamerasPerCall = 64;

// Bad flag values: reported like CLI11's own errors, exit code kExitUsage.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Vector {
  double x, y, z;
};

Vector parseVector(const std::string& text, const char* flag) {
  const std::optional<TypedVector> v = parseXyz(text);
  if (!v) throw UsageError(fmt::format("{} expects X,Y,Z (got \"{}\")", flag, text));
  return {v->x, v->y, v->z};
}

v1::Vec3 toProto(const Vector& v) {
  v1::Vec3 out;
  out.set_x(v.x), out.set_y(v.y), out.set_z(v.z);
  return out;
}

// Rodrigues' rotation of v by `angle` radians about the unit axis k.
Vector rotate(const Vector& v, const Vector& k, double angle) {
  double c = std::cos(angle), s = std::sin(angle);
  double kv = k.x * v.x + k.y * v.y + k.z * v.z;
  Vector kxv{k.y * v.z - k.z * v.y, k.z * v.x - k.x * v.z, k.x * v.y - k.y * v.x};
  return {v.x * c + kxv.x * s + k.x * kv * (1 - c), v.y * c + kxv.y * s + k.y * kv * (1 - c),
          v.z * c + kxv.z * s + k.z * kv * (1 - c)};
}

// One camera, or `turntable` cameras whose eyes orbit the target about the up axis (through
// the target), starting at --eye.
std::vector<v1::Camera> buildCameras(const RemoteRenderArgs& a) {
  if (a.eye.empty() || a.target.empty()) throw UsageError("--eye and --target are required");
  Vector eye = parseVector(a.eye, "--eye");
  Vector target = parseVector(a.target, "--target");
  Vector up = parseVector(a.up, "--up");
  v1::Camera base;
  *base.mutable_target() = toProto(target);
  *base.mutable_up() = toProto(up);
  base.set_fov_y_deg(a.fovDeg);
  const std::optional<TypedSize> size = parseWxH(a.size);
  if (!size) throw UsageError(fmt::format("--size expects WIDTHxHEIGHT (got \"{}\")", a.size));
  base.set_width(size->width);
  base.set_height(size->height);
  if (a.turntable < 0) throw UsageError("--turntable expects a positive number of frames");
  const int count = std::max(1, a.turntable);
  double upLength = std::sqrt(up.x * up.x + up.y * up.y + up.z * up.z);
  if (a.turntable > 0 && !(upLength > 0)) throw UsageError("--turntable needs a non-zero --up");
  Vector axis{up.x / upLength, up.y / upLength, up.z / upLength};
  Vector offset{eye.x - target.x, eye.y - target.y, eye.z - target.z};
  std::vector<v1::Camera> cameras;
  for (int i = 0; i < count; ++i) {
    v1::Camera camera = base;
    if (a.turntable > 0) {
      Vector r = rotate(offset, axis, 2 * M_PI * i / count);
      *camera.mutable_eye() = toProto({target.x + r.x, target.y + r.y, target.z + r.z});
    } else {
      *camera.mutable_eye() = toProto(eye);
    }
    cameras.push_back(camera);
  }
  return cameras;
}

v1::ImageFormat chooseFormat(const RemoteRenderArgs& a) {
  std::string name = a.format;
  if (name.empty()) {
    std::string ext = std::filesystem::path(a.output).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    name = ext == ".jpg" || ext == ".jpeg"   ? "jpeg"
           : ext == ".exr"                   ? "exr"
           : ext == ".raw" || ext == ".rgba" ? "raw"
                                             : "png";
  }
  if (name == "png") return v1::IMAGE_FORMAT_PNG;
  if (name == "jpeg" || name == "jpg") return v1::IMAGE_FORMAT_JPEG;
  if (name == "exr") return v1::IMAGE_FORMAT_EXR;
  if (name == "raw") return v1::IMAGE_FORMAT_RAW_RGBA;
  throw UsageError(fmt::format("--format expects png, jpeg, exr or raw (got \"{}\")", name));
}

v1::RenderSettings buildSettings(const RemoteRenderArgs& a) {
  v1::RenderSettings s;
  int modes =
      int(a.pixelAccuracy.has_value()) + int(a.tolerance.has_value()) + int(a.level.has_value());
  if (modes > 1) throw UsageError("give at most one of --pixel-accuracy, --tolerance and --level");
  if (a.pixelAccuracy) s.set_pixel_accuracy(*a.pixelAccuracy);
  if (a.tolerance) s.set_absolute_tolerance(*a.tolerance);
  if (a.level) s.set_uniform_level(*a.level);
  if (a.eta) s.set_eta(*a.eta);
  if (a.maxTriangles) s.set_max_triangles(*a.maxTriangles);
  if (a.noCrackFilling) s.set_crack_filling(false);
  s.set_format(chooseFormat(a));
  if (a.quality) {
    if (s.format() != v1::IMAGE_FORMAT_JPEG) throw UsageError("--quality applies to JPEG only");
    s.set_jpeg_quality(*a.quality);
  }
  return s;
}

std::string toHex(const unsigned char* digest, unsigned int length) {
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

struct WrittenFrame {
  std::string file;
  v1::FrameHeader header;
};

// A failure while receiving: the exit code and what to print.
struct Failure {
  int exitCode;
  std::string message;
};

// Writes one frame's chunks to FILE.partial (StagedOutput), then checks size and checksum and renames it.
class FrameFile {
 public:
  FrameFile(std::string file, v1::FrameHeader header)
      : file_(std::move(file)),
        staged_(file_),
        header_(std::move(header)),
        out_(staged_.path(), std::ios::binary | std::ios::trunc),
        digest_(EVP_MD_CTX_new(), &EVP_MD_CTX_free) {
    EVP_DigestInit_ex(digest_.get(), EVP_sha256(), nullptr);
    if (!out_) throw Failure{kExitIo, fmt::format("cannot write {}", staged_.path())};
  }
  ~FrameFile() {
    if (done_) return;
    out_.close();
    staged_.discard();
  }

  bool complete() const { return written_ == header_.image_bytes(); }

  void append(const v1::ImageChunk& chunk) {
    if (chunk.offset() != written_) {
      throw Failure{kExitRemote, fmt::format("{}: chunk at offset {}, expected {}", file_,
                                             chunk.offset(), written_)};
    }
    if (written_ + int64_t(chunk.data().size()) > header_.image_bytes()) {
      throw Failure{kExitRemote, fmt::format("{}: more bytes than the header's {}", file_,
                                             header_.image_bytes())};
    }
    out_.write(chunk.data().data(), std::streamsize(chunk.data().size()));
    EVP_DigestUpdate(digest_.get(), chunk.data().data(), chunk.data().size());
    written_ += int64_t(chunk.data().size());
  }

  WrittenFrame finish() {
    unsigned char hash[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    EVP_DigestFinal_ex(digest_.get(), hash, &length);
    out_.close();
    if (!out_) throw Failure{kExitIo, fmt::format("cannot write {}", staged_.path())};
    if (toHex(hash, length) != header_.image_sha256()) {
      throw Failure{kExitRemote,
                    fmt::format("{}: the image's SHA-256 does not match the header", file_)};
    }
    if (const std::error_code error = staged_.publish()) throw Failure{kExitIo, fmt::format("cannot write {}: {}", file_, error.message())};
    done_ = true;
    return {file_, header_};
  }

 private:
  std::string file_;
  StagedOutput staged_;
  v1::FrameHeader header_;
  std::ofstream out_;
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> digest_;
  int64_t written_ = 0;
  bool done_ = false;
};

// Receives the frames of one call (cameras first .. first + count - 1 of total).
void receiveFrames(grpc::ClientReader<v1::RenderResponse>& reader, const RemoteRenderArgs& args,
                   int first, int count, int total, ProgressBar& bar,
                   std::vector<WrittenFrame>& written) {
  std::unique_ptr<FrameFile> current;
  int expected = 0;
  v1::RenderResponse message;
  while (reader.Read(&message)) {
    if (message.has_header()) {
      const v1::FrameHeader& header = message.header();
      if (current || header.index() != expected || expected >= count) {
        throw Failure{kExitRemote,
                      fmt::format("unexpected frame header (index {})", header.index())};
      }
      current =
          std::make_unique<FrameFile>(frameFileName(args.output, first + expected, total), header);
      ++expected;
    } else if (message.has_chunk()) {
      if (!current) throw Failure{kExitRemote, "image data before a frame header"};
      current->append(message.chunk());
    }
    if (current && current->complete()) {
      written.push_back(current->finish());
      current.reset();
      bar.update(double(written.size()) / total, written.back().file);
    }
  }
}

void printFrame(const WrittenFrame& f) {
  const v1::FrameHeader& h = f.header;
  const v1::FrameTimings& t = h.timings();
  const v1::FrameStatistics& s = h.statistics();
  const char* format = h.format() == v1::IMAGE_FORMAT_JPEG       ? "jpeg"
                       : h.format() == v1::IMAGE_FORMAT_EXR      ? "exr"
                       : h.format() == v1::IMAGE_FORMAT_RAW_RGBA ? "raw rgba"
                                                                 : "png";
  std::cout << fmt::format("wrote {} ({}x{} {}, {}) on {}\n", f.file, h.width(), h.height(), format,
                           humanBytes(h.image_bytes()), h.device())
            << fmt::format(
                   "  triangles {}  pieces {} ({} visible, {} patches drawn)  rings {}  "
                   "ring depth avg {:.2f} max {}\n",
                   s.triangles(), s.pieces(), s.visible_pieces(), s.render_patches(), s.rings(),
                   s.average_ring_depth(), s.max_ring_depth())
            << fmt::format(
                   "  wait {:.1f} ms  plan {:.1f} ms  tessellation {:.1f} ms  "
                   "raster+shading {:.1f} ms  crack filling {:.1f} ms  encode {:.1f} ms  "
                   "(render call {:.1f} ms; GPU stages {})\n",
                   t.wait_ms(), t.plan_ms(), t.tessellation_ms(), t.raster_shading_ms(),
                   t.crack_filling_ms(), t.encode_ms(), t.render_ms(),
                   t.gpu_timestamps() ? "from device timestamps" : "timed on the host");
}

}  // namespace

std::string frameFileName(const std::string& output, int index, int count) {
  if (count <= 1 && output.find('%') == std::string::npos) return output;
  static const std::regex placeholder("%0?[0-9]*d");
  std::smatch match;
  if (output.find('%') != std::string::npos) {
    if (!std::regex_search(output, match, placeholder) ||
        std::count(output.begin(), output.end(), '%') != 1) {
      throw std::invalid_argument(
          fmt::format("-o: \"{}\" must have exactly one %d-style placeholder", output));
    }
    std::string spec = match.str();
    int width = spec.size() > 2 ? std::stoi(spec.substr(1, spec.size() - 2)) : 0;
    return match.prefix().str() + fmt::format("{:0{}d}", index, width) + match.suffix().str();
  }
  std::filesystem::path path(output);
  std::string stem = path.stem().string();
  std::filesystem::path name = fmt::format("{}-{:03d}{}", stem, index, path.extension().string());
  return (path.parent_path() / name).string();
}

int runRemoteRender(const RemoteEndpoint& endpoint, const RemoteRenderArgs& args) {
  std::vector<v1::Camera> cameras;
  v1::RenderRequest base;
  try {
    if (args.output.empty()) throw UsageError("-o FILE is required");
    cameras = buildCameras(args);
    *base.mutable_settings() = buildSettings(args);
    base.set_name(asMeshName(args.mesh));
    frameFileName(args.output, 0, int(cameras.size()));  // checks the pattern
  } catch (const std::exception& e) {
    std::cerr << "tessera render: " << e.what() << "\n";
    return kExitUsage;
  }
  auto stub = v1::RenderService::NewStub(makeChannel(endpoint));
  const int total = int(cameras.size());
  std::vector<WrittenFrame> written;
  ProgressBar bar("render");
  bar.update(0.0, fmt::format("{} frame{}", total, total == 1 ? "" : "s"));
  for (int first = 0; first < total; first += kCamerasPerCall) {
    const int count = std::min(kCamerasPerCall, total - first);
    v1::RenderRequest request = base;
    for (int i = first; i < first + count; ++i) *request.add_cameras() = cameras[size_t(i)];
    grpc::ClientContext context;
    std::optional<std::chrono::seconds> timeout;
    if (args.timeoutSeconds) timeout = std::chrono::seconds(*args.timeoutSeconds);
    prepareContext(context, endpoint, timeout);
    auto reader = stub->Render(&context, request);
    std::optional<Failure> failure;
    try {
      receiveFrames(*reader, args, first, count, total, bar, written);
    } catch (const Failure& f) {
      failure = f;
      context.TryCancel();
    }
    grpc::Status status = reader->Finish();
    if (failure) {
      bar.finish();
      std::cerr << fmt::format("tessera: render {}: {}\n", request.name(), failure->message);
      return failure->exitCode;
    }
    if (!status.ok()) {
      bar.finish();
      return reportRpcError("render " + request.name(), status, &context);
    }
    if (int(written.size()) != first + count) {
      bar.finish();
      std::cerr << fmt::format("tessera: render {}: the server sent {} of {} frames\n",
                               request.name(), int(written.size()) - first, count);
      return kExitRemote;
    }
  }
  bar.finish();
  for (const WrittenFrame& f : written) printFrame(f);
  return kExitOk;
}

void registerRenderCommand(CLI::App& app, CommandContext& context) {
  auto args = std::make_shared<RemoteRenderArgs>();
  CLI::App* render = app.add_subcommand("render", "Render a stored mesh on the server to images");
  render->add_option("mesh", args->mesh, "meshes/NAME")->required();
  render
      ->add_option("-o,--output", args->output,
                   "Image file; with --turntable a pattern (frame.png -> frame-000.png, or "
                   "frame-%04d.png)")
      ->required();
  render->add_option("--eye", args->eye, "Camera position X,Y,Z")->required();
  render->add_option("--target", args->target, "Point the camera looks at, X,Y,Z")->required();
  render->add_option("--up", args->up, "Camera up vector X,Y,Z")->capture_default_str();
  render->add_option("--fov", args->fovDeg, "Vertical field of view in degrees")
      ->capture_default_str();
  render->add_option("--size", args->size, "Image WIDTHxHEIGHT")->capture_default_str();
  auto* pixel = render->add_option("--pixel-accuracy", args->pixelAccuracy,
                                   "Screen-space tolerance in pixels (default 0.5)");
  auto* tolerance =
      render->add_option("--tolerance", args->tolerance, "Object-space tolerance in model units");
  auto* level =
      render->add_option("--level", args->level, "Uniform tessellation level (e.g. 16, 32, 64)");
  pixel->excludes(tolerance)->excludes(level);
  tolerance->excludes(level);
  render->add_option("--eta", args->eta,
                     "Share of the tolerance for the Bezier approximation (0..1)");
  render->add_option("--max-triangles", args->maxTriangles,
                     "Refuse frames past this many triangles");
  render
      ->add_option("--format", args->format, "png, jpeg, exr or raw (default: from -o's extension)")
      ->check(CLI::IsMember({"png", "jpeg", "jpg", "exr", "raw"}));
  render->add_option("--quality", args->quality, "JPEG quality 1..100 (default 90)");
  render->add_flag("--no-crack-filling", args->noCrackFilling, "Skip the crack-filling pass");
  render
      ->add_option("--turntable", args->turntable,
                   "Render N cameras orbiting the target about the up axis")
      ->check(CLI::PositiveNumber);
  render->add_option("--timeout", args->timeoutSeconds, "Deadline for each call, in seconds");
  render->callback(
      [&app, &context, args] { context.exitCode = runRemoteRender(endpointFromApp(app), *args); });
}

}  // namespace tessera::cli
