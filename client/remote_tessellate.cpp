#include "client/remote_tessellate.h"

#include <fmt/format.h>
#include <openssl/evp.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "client/commands.h"
#include "client/remote_progress.h"
#include "client/remote_staged_output.h"
#include "core/base/error.h"
#include "core/output/glb_writer.h"
#include "core/request/camera_text.h"
#include "tessera/v1/tessellation.grpc.pb.h"

namespace tessera::cli {
namespace {

namespace v1 = tessera::v1;

// Bad flag values: reported like CLI11's own errors, exit code kExitUsage.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

v1::Vec3 parseVec3(const std::string& text, const char* flag) {
  const std::optional<TypedVector> parsed = parseXyz(text);
  if (!parsed) throw UsageError(fmt::format("{} expects X,Y,Z (got \"{}\")", flag, text));
  v1::Vec3 v;
  v.set_x(parsed->x), v.set_y(parsed->y), v.set_z(parsed->z);
  return v;
}

void parseSize(const std::string& text, v1::Camera& camera) {
  const std::optional<TypedSize> size = parseWxH(text);
  if (!size) throw UsageError(fmt::format("--size expects WIDTHxHEIGHT (got \"{}\")", text));
  camera.set_width(size->width);
  camera.set_height(size->height);
}

void setPixelTolerance(const RemoteTessellateArgs& a, v1::TessellateRequest& request) {
  if (a.eye.empty() || a.target.empty() || a.up.empty() || !a.fovDeg || a.size.empty()) {
    throw UsageError("a camera needs all of --eye, --target, --up, --fov and --size");
  }
  if (a.tolerance) throw UsageError("give --tolerance or a camera (--eye ...), not both");
  v1::PixelTolerance* pixel = request.mutable_pixel();
  v1::Camera* camera = pixel->mutable_camera();
  *camera->mutable_eye() = parseVec3(a.eye, "--eye");
  *camera->mutable_target() = parseVec3(a.target, "--target");
  *camera->mutable_up() = parseVec3(a.up, "--up");
  camera->set_fov_y_deg(*a.fovDeg);
  parseSize(a.size, *camera);
  if (a.pixelAccuracy) pixel->set_pixel_accuracy(*a.pixelAccuracy);
}

// The request's encoding for a name core knows (core/output/glb_writer.h).
v1::GlbEncoding protoEncoding(const std::string& name) {
  GlbEncoding encoding;
  try {
    encoding = parseGlbEncoding(name);
  } catch (const TesseraError& e) {
    throw UsageError(std::string("--encoding: ") + e.what());
  }
  switch (encoding) {
    case GlbEncoding::kQuantized: return v1::GLB_ENCODING_QUANTIZED;
    case GlbEncoding::kMeshopt: return v1::GLB_ENCODING_MESHOPT;
    case GlbEncoding::kFloat: break;
  }
  return v1::GLB_ENCODING_FLOAT;
}

v1::TessellateRequest buildRequest(const RemoteTessellateArgs& a) {
  v1::TessellateRequest request;
  request.set_name(a.meshName);
  bool camera = !a.eye.empty() || !a.target.empty() || !a.up.empty() || a.fovDeg || !a.size.empty();
  if (camera) {
    setPixelTolerance(a, request);
  } else if (!a.tolerance) {
    if (!a.level) throw UsageError("give --tolerance, --level, or a camera (--eye, --target, ...)");
  } else if (a.relative) {
    request.set_relative(*a.tolerance);
  } else {
    request.set_absolute(*a.tolerance);
  }
  if (a.relative && camera) throw UsageError("--relative does not apply to a camera");
  if (a.pixelAccuracy && !camera) throw UsageError("--pixel-accuracy needs a camera");
  if (a.eta) request.set_eta(*a.eta);
  if (a.level) request.set_uniform_level(*a.level);
  if (a.maxTriangles) request.set_max_triangles(*a.maxTriangles);
  if (!a.encoding.empty()) request.set_encoding(protoEncoding(a.encoding));
  if (a.output.empty()) throw UsageError("-o OUT.glb is required");
  return request;
}

std::string toHex(const unsigned char* digest, unsigned int length) {
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

// Receives the stream into a temporary file next to the output; returns the summary once the
// bytes, offsets and checksum agree with it.
struct Received {
  std::optional<v1::TessellationSummary> summary;
  std::string problem;  // why the stream is unusable, if it is
};

Received receive(grpc::ClientReader<v1::TessellateResponse>& reader, std::ofstream& out) {
  using Digest = std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)>;
  Digest digest(EVP_MD_CTX_new(), &EVP_MD_CTX_free);
  EVP_DigestInit_ex(digest.get(), EVP_sha256(), nullptr);
  ProgressBar bar("tessellate");
  Received result;
  int64_t written = 0;
  v1::TessellateResponse message;
  while (reader.Read(&message)) {
    if (message.has_progress()) {
      bar.update(message.progress().fraction(), message.progress().stage());
    } else if (message.has_glb_chunk()) {
      const v1::GlbChunk& chunk = message.glb_chunk();
      if (chunk.offset() != written) {
        result.problem = fmt::format("chunk at offset {}, expected {}", chunk.offset(), written);
      }
      out.write(chunk.data().data(), static_cast<std::streamsize>(chunk.data().size()));
      EVP_DigestUpdate(digest.get(), chunk.data().data(), chunk.data().size());
      written += static_cast<int64_t>(chunk.data().size());
      bar.update(1.0, humanBytes(written));
    } else if (message.has_summary()) {
      result.summary = message.summary();
    }
  }
  bar.finish();
  unsigned char hash[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_DigestFinal_ex(digest.get(), hash, &length);
  if (result.summary && result.problem.empty()) {
    if (result.summary->glb_size() != written) {
      result.problem = fmt::format("received {} bytes, the summary says {}", written,
                                   result.summary->glb_size());
    } else if (result.summary->glb_sha256() != toHex(hash, length)) {
      result.problem = "the GLB's SHA-256 does not match the summary";
    }
  }
  return result;
}

void printSummary(const v1::TessellationSummary& s, const std::string& output) {
  std::cout << fmt::format("wrote {} ({})\n", output, humanBytes(s.glb_size()))
            << fmt::format("triangles {}  patches {}  rings {}  depth avg {:.2f} max {}\n",
                           s.triangles(), s.patches(), s.rings(), s.average_depth(), s.max_depth())
            << fmt::format("tolerance {:g}  guaranteed bound {:g}\n", s.tolerance(),
                           s.guaranteed_bound());
  for (const v1::StageTiming& t : s.timings()) {
    std::cout << fmt::format("  {:<14} {:.3f} s\n", t.stage(), t.seconds());
  }
}

}  // namespace

bool isRemoteMeshName(std::string_view argument) {
  return argument.substr(0, 7) == "meshes/";
}

int runRemoteTessellate(const CLI::App& root, const RemoteTessellateArgs& args) {
  return runRemoteTessellate(endpointFromApp(root), args);
}

int runRemoteTessellate(const RemoteEndpoint& endpoint, const RemoteTessellateArgs& args) {
  v1::TessellateRequest request;
  try {
    request = buildRequest(args);
  } catch (const UsageError& e) {
    std::cerr << "tessera tessellate: " << e.what() << "\n";
    return kExitUsage;
  }
  const StagedOutput staged(args.output);
  std::ofstream out(staged.path(), std::ios::binary | std::ios::trunc);
  if (!out) {
    std::cerr << fmt::format("tessera: cannot write {}\n", staged.path());
    return kExitIo;
  }
  auto stub = v1::TessellationService::NewStub(makeChannel(endpoint));
  grpc::ClientContext context;
  std::optional<std::chrono::seconds> timeout;
  if (args.timeoutSeconds) timeout = std::chrono::seconds(*args.timeoutSeconds);
  prepareContext(context, endpoint, timeout);
  auto reader = stub->Tessellate(&context, request);
  Received received = receive(*reader, out);
  grpc::Status status = reader->Finish();
  out.close();
  if (!status.ok()) {
    staged.discard();
    return reportRpcError("tessellate " + args.meshName, status, &context);
  }
  if (!received.summary || !received.problem.empty() || !out) {
    staged.discard();
    std::cerr << fmt::format("tessera: tessellate {}: incomplete result: {}\n", args.meshName,
                             received.problem.empty() ? "no summary" : received.problem);
    return kExitRemote;
  }
  if (const std::error_code error = staged.publish()) {
    std::cerr << fmt::format("tessera: cannot write {}: {}\n", args.output, error.message());
    return kExitIo;
  }
  printSummary(*received.summary, args.output);
  return kExitOk;
}

}  // namespace tessera::cli
