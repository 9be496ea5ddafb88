#include "client/remote_bench_calls.h"

#include <fmt/format.h>
#include <openssl/evp.h>

#include <cstdlib>
#include <string>

#include "tessera/status_names.h"

namespace tessera::cli {
namespace {

namespace v1 = tessera::v1;

int64_t sizeOf(const google::protobuf::Message& message) {
  return static_cast<int64_t>(message.ByteSizeLong());
}

// The retry hint a refusal carries (0 without one).
int64_t pushbackMs(const grpc::ClientContext& context) {
  const auto& trailers = context.GetServerTrailingMetadata();
  const auto hint = trailers.find("grpc-retry-pushback-ms");
  return hint == trailers.end() ? 0 : std::strtoll(std::string(hint->second.data(), hint->second.size()).c_str(), nullptr, 10);
}

// Incremental SHA-256 of the GLB as it streams in, so that the client holds no copy of it.
class StreamDigest {
 public:
  StreamDigest() : context_(EVP_MD_CTX_new(), &EVP_MD_CTX_free) {
    EVP_DigestInit_ex(context_.get(), EVP_sha256(), nullptr);
  }
  void update(const std::string& bytes) {
    EVP_DigestUpdate(context_.get(), bytes.data(), bytes.size());
  }
  std::string hex() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    EVP_DigestFinal_ex(context_.get(), digest, &length);
    std::string text;
    text.reserve(2 * length);
    for (unsigned int i = 0; i < length; ++i) text += fmt::format("{:02x}", digest[i]);
    return text;
  }

 private:
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context_;
};

}  // namespace

std::string_view benchOpName(BenchOp op) {
  switch (op) {
    case BenchOp::kTessellate:
      return "tessellate";
    case BenchOp::kGet:
      return "get";
    case BenchOp::kList:
      return "list";
    case BenchOp::kInfo:
      return "info";
    case BenchOp::kUpload:
      return "upload";
  }
  return "unknown";
}

std::optional<BenchOp> mixOpFromName(std::string_view name) {
  for (BenchOp op : kMixOps) {
    if (benchOpName(op) == name) return op;
  }
  return std::nullopt;
}

std::string CallOutcome::errorName() const {
  if (code == grpc::StatusCode::OK) return badStream ? "BAD_STREAM" : "OK";
  return std::string(statusCodeName(code));
}

BenchClient::BenchClient(std::shared_ptr<grpc::Channel> channel, const RemoteEndpoint& endpoint,
                         const BenchRequests& requests)
    : endpoint_(endpoint),
      requests_(requests),
      meshes_(v1::MeshService::NewStub(channel)),
      tessellation_(v1::TessellationService::NewStub(channel)),
      info_(v1::ServerInfoService::NewStub(channel)) {}

void BenchClient::prepare(grpc::ClientContext& context) const {
  prepareContext(context, endpoint_);
  context.set_deadline(std::chrono::system_clock::now() + requests_.timeout);
}

CallOutcome BenchClient::call(BenchOp op, uint64_t sequence) {
  CallOutcome outcome;
  grpc::ClientContext context;
  switch (op) {
    case BenchOp::kTessellate:
      return tessellate(requests_.tessellate[sequence % requests_.tessellate.size()]);
    case BenchOp::kGet: {
      const v1::GetMeshRequest& request = requests_.get[sequence % requests_.get.size()];
      prepare(context);
      v1::Mesh response;
      outcome.code = meshes_->GetMesh(&context, request, &response).error_code();
      outcome.retryAfterMs = pushbackMs(context);
      outcome.bytesSent = sizeOf(request);
      outcome.bytesReceived = sizeOf(response);
      return outcome;
    }
    case BenchOp::kList: {
      prepare(context);
      v1::ListMeshesResponse response;
      outcome.code = meshes_->ListMeshes(&context, requests_.list, &response).error_code();
      outcome.retryAfterMs = pushbackMs(context);
      outcome.bytesSent = sizeOf(requests_.list);
      outcome.bytesReceived = sizeOf(response);
      return outcome;
    }
    case BenchOp::kInfo: {
      prepare(context);
      v1::GetServerInfoRequest request;
      v1::ServerInfo response;
      outcome.code = info_->GetServerInfo(&context, request, &response).error_code();
      outcome.retryAfterMs = pushbackMs(context);
      outcome.bytesSent = sizeOf(request);
      outcome.bytesReceived = sizeOf(response);
      return outcome;
    }
    case BenchOp::kUpload:
      break;  // not a mix operation: upload() takes the mesh
  }
  return outcome;
}

CallOutcome BenchClient::upload(const v1::MeshArrays& arrays, const UploadOptions& options) {
  CallOutcome outcome;
  grpc::ClientContext context;
  prepare(context);
  v1::Mesh mesh;
  outcome.code = uploadMeshArrays(*meshes_, context, arrays, options, &mesh).error_code();
  outcome.retryAfterMs = pushbackMs(context);
  outcome.bytesSent = sizeOf(arrays);
  outcome.bytesReceived = sizeOf(mesh);
  return outcome;
}

CallOutcome BenchClient::tessellate(const v1::TessellateRequest& request) {
  CallOutcome outcome;
  outcome.bytesSent = sizeOf(request);
  grpc::ClientContext context;
  prepare(context);
  auto reader = tessellation_->Tessellate(&context, request);
  StreamDigest digest;
  int64_t glbBytes = 0;
  bool ordered = true;
  std::optional<v1::TessellationSummary> summary;
  v1::TessellateResponse message;
  while (reader->Read(&message)) {
    outcome.bytesReceived += sizeOf(message);
    if (message.has_glb_chunk()) {
      const v1::GlbChunk& chunk = message.glb_chunk();
      ordered = ordered && chunk.offset() == glbBytes && !summary;
      glbBytes += static_cast<int64_t>(chunk.data().size());
      if (requests_.verifyChecksum) digest.update(chunk.data());
    } else if (message.has_summary()) {
      summary = message.summary();
    }
  }
  outcome.code = reader->Finish().error_code();
  outcome.retryAfterMs = pushbackMs(context);
  if (summary) {
    outcome.serverSeconds = 0;
    for (const v1::StageTiming& stage : summary->timings())
      outcome.serverSeconds += stage.seconds();
  }
  if (outcome.code == grpc::StatusCode::OK) {
    outcome.badStream = !summary || !ordered || summary->glb_size() != glbBytes ||
                        (requests_.verifyChecksum && summary->glb_sha256() != digest.hex());
  }
  return outcome;
}

}  // namespace tessera::cli
