#include "server/http/http_front_door.h"

#include <fmt/format.h>
#include <google/protobuf/empty.pb.h>
#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <google/protobuf/util/json_util.h>
#include <httplib.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>

#include "core/base/sha256.h"
#include "core/request/camera_text.h"
#include "server/calls/status_error.h"
#include "server/http/http_query.h"
#include "server/http/http_status.h"
#include "tessera/v1/mesh.grpc.pb.h"
#include "tessera/v1/render.grpc.pb.h"
#include "tessera/v1/tessellation.grpc.pb.h"

namespace tessera::server {

namespace v1 = tessera::v1;

struct HttpFrontDoor::Services {
  HttpFrontDoorOptions options;
  std::unique_ptr<v1::MeshService::Stub> meshes;
  std::unique_ptr<v1::TessellationService::Stub> tessellation;
  std::unique_ptr<v1::RenderService::Stub> render;
};

namespace {

constexpr size_t kUploadChunkBytes = 64 << 10;  // as the API advises for obj_data
// What is still read of a refused upload's body, so that closing the connection does not reset it
// before the client has read the refusal; a longer body is cut off.
constexpr size_t kDrainBytes = 1 << 20;

// gRPC metadata takes printable ASCII only; anything else is the client's mistake.
std::string headerForMetadata(const httplib::Request& request, const char* name) {
  std::string value = request.get_header_value(name);
  for (char c : value) {
    if (c < 0x20 || c > 0x7e) throwInvalidArgument(fmt::format("header {}: printable ASCII only", name));
  }
  return value;
}

// The call's context: the client's token, request id and deadline.
std::unique_ptr<grpc::ClientContext> contextFor(const httplib::Request& request) {
  auto context = std::make_unique<grpc::ClientContext>();
  if (std::string token = headerForMetadata(request, "Authorization"); !token.empty()) {
    context->AddMetadata("authorization", token);
  }
  if (std::string id = headerForMetadata(request, "X-Request-Id"); !id.empty()) context->AddMetadata("x-request-id", id);
  if (const std::optional<int64_t> ms = queryNumber<int64_t>(request.params, "timeout_ms")) {
    if (*ms <= 0) throwInvalidArgument(fmt::format("query parameter timeout_ms: must be positive (got {})", *ms));
    context->set_deadline(std::chrono::system_clock::now() + std::chrono::milliseconds(*ms));
  }
  return context;
}

std::string metadataValue(const std::multimap<grpc::string_ref, grpc::string_ref>& metadata, const char* key) {
  auto found = metadata.find(key);
  return found == metadata.end() ? std::string() : std::string(found->second.data(), found->second.size());
}

void copyRequestId(const grpc::ClientContext& context, httplib::Response& response) {
  const std::string id = metadataValue(context.GetServerInitialMetadata(), "x-request-id");
  if (!id.empty()) response.set_header("X-Request-Id", id);
}

// A failed call as its HTTP response, with the server's retry hint as Retry-After.
void respondWithStatus(const grpc::Status& status, const grpc::ClientContext* context, httplib::Response& response) {
  response.status = httpStatusFor(status.error_code());
  response.set_content(errorJson(status), "application/json");
  if (status.error_code() == grpc::StatusCode::UNAUTHENTICATED) response.set_header("WWW-Authenticate", "Bearer");
  if (!context) return;
  copyRequestId(*context, response);
  const std::string pushback = metadataValue(context->GetServerTrailingMetadata(), "grpc-retry-pushback-ms");
  if (!pushback.empty()) {
    const int64_t ms = std::max<int64_t>(1, std::atoll(pushback.c_str()));
    response.set_header("Retry-After", std::to_string((ms + 999) / 1000));
  }
}

void respondWithJson(const google::protobuf::Message& message, int status, httplib::Response& response) {
  std::string json;
  (void)google::protobuf::util::MessageToJsonString(message, &json);
  response.status = status;
  response.set_content(json, "application/json");
}

// Runs a route: its StatusErrors (bad query parameters) become their HTTP responses, anything
// unexpected a 500 whose cause goes to the log only.
template <typename Route>
httplib::Server::Handler guarded(Route route) {
  return [route](const httplib::Request& request, httplib::Response& response) {
    try {
      route(request, response);
    } catch (const StatusError& error) {
      respondWithStatus(error.status(), nullptr, response);
    } catch (const std::exception& error) {
      spdlog::error("http {} {}: internal error: {}", request.method, request.path, error.what());
      respondWithStatus(grpc::Status(grpc::StatusCode::INTERNAL, "internal error"), nullptr, response);
    }
  };
}

void listMeshes(const HttpFrontDoor::Services& s, const httplib::Request& request, httplib::Response& response) {
  checkQueryParameters(request.params, {"page_size", "page_token"});
  v1::ListMeshesRequest list;
  if (const std::optional<int32_t> size = queryNumber<int32_t>(request.params, "page_size")) list.set_page_size(*size);
  list.set_page_token(request.get_param_value("page_token"));
  auto context = contextFor(request);
  v1::ListMeshesResponse page;
  const grpc::Status status = s.meshes->ListMeshes(context.get(), list, &page);
  if (!status.ok()) return respondWithStatus(status, context.get(), response);
  copyRequestId(*context, response);
  respondWithJson(page, 200, response);
}

void getMesh(const HttpFrontDoor::Services& s, const httplib::Request& request, httplib::Response& response) {
  checkQueryParameters(request.params, {});
  v1::GetMeshRequest get;
  get.set_name("meshes/" + std::string(request.matches[1]));
  auto context = contextFor(request);
  v1::Mesh mesh;
  const grpc::Status status = s.meshes->GetMesh(context.get(), get, &mesh);
  if (!status.ok()) return respondWithStatus(status, context.get(), response);
  copyRequestId(*context, response);
  respondWithJson(mesh, 200, response);
}

void deleteMesh(const HttpFrontDoor::Services& s, const httplib::Request& request, httplib::Response& response) {
  checkQueryParameters(request.params, {});
  v1::DeleteMeshRequest remove;
  remove.set_name("meshes/" + std::string(request.matches[1]));
  auto context = contextFor(request);
  google::protobuf::Empty empty;
  const grpc::Status status = s.meshes->DeleteMesh(context.get(), remove, &empty);
  if (!status.ok()) return respondWithStatus(status, context.get(), response);
  copyRequestId(*context, response);
  response.status = 204;
}

// What is still read of a refused upload's body (kDrainBytes at most), then the 411 or 400.
void refuseBody(const httplib::ContentReader& body, int httpStatus, const std::string& message,
                httplib::Response& response) {
  // Read (a bounded part of) what was sent, so that closing does not reset the connection
  // before the client has read the answer.
  size_t drained = 0;
  body([&](const char*, size_t size) { return (drained += size) < kDrainBytes; });
  response.status = httpStatus;
  response.set_content(errorJson(grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message)), "application/json");
}

// A positions-only upload's body (mesh.proto, UploadMeshHeader.topology_of): little-endian
// 32-bit floats, the positions then `uvValues` UV numbers, sent on as MeshArrays pieces of about
// kUploadChunkBytes. A float may straddle two pieces of the body.
class FloatBody {
 public:
  explicit FloatBody(int64_t positions) : positions_(positions) {}
  // Takes the bytes; true when a piece is full.
  bool append(const char* data, size_t size) {
    carry_.append(data, size);
    const size_t whole = carry_.size() / 4 * 4;
    for (size_t at = 0; at < whole; at += 4) {
      const auto* b = reinterpret_cast<const unsigned char*>(carry_.data() + at);
      const uint32_t bits = uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
      float value;
      std::memcpy(&value, &bits, sizeof value);
      v1::MeshArrays& arrays = *piece_.mutable_arrays();
      if (index_++ < positions_) arrays.add_positions(value); else arrays.add_uvs(value);
    }
    carry_.erase(0, whole);
    return int64_t(piece_.arrays().positions_size() + piece_.arrays().uvs_size()) * 4 >= int64_t(kUploadChunkBytes);
  }
  bool empty() const { return piece_.arrays().positions_size() + piece_.arrays().uvs_size() == 0; }
  // The piece to send; the next starts empty.
  v1::UploadMeshRequest take() { return std::exchange(piece_, {}); }

 private:
  int64_t positions_;
  int64_t index_ = 0;
  std::string carry_;
  v1::UploadMeshRequest piece_;
};

// The header of a positions-only upload from its query parameters; its first data message (the
// origin, if given) in *origin.
void positionsHeader(const httplib::Request& request, int64_t length, v1::UploadMeshHeader& header,
                     v1::UploadMeshRequest* origin, int64_t* positions) {
  std::string topologyOf = request.get_param_value("topology_of");
  if (topologyOf.rfind("meshes/", 0) != 0) topologyOf = "meshes/" + topologyOf;  // ID or meshes/ID
  header.set_topology_of(topologyOf);
  header.set_format(v1::MESH_FORMAT_ARRAYS);
  const int64_t uvValues = queryNumber<int64_t>(request.params, "uv_values").value_or(0);
  if (uvValues < 0 || uvValues > length / 4) {
    throwInvalidArgument(fmt::format("query parameter uv_values: {} UV numbers, where the body holds {} floats",
                                     uvValues, length / 4));
  }
  *positions = length / 4 - uvValues;
  int64_t total = length;
  if (const std::optional<std::string> text = queryParameter(request.params, "origin")) {
    const std::optional<TypedVector> v = parseXyz(*text);
    if (!v) throwInvalidArgument(fmt::format("query parameter origin: expects X,Y,Z, got {}", quoteForMessage(*text)));
    v1::Vec3& o = *origin->mutable_arrays()->mutable_origin();
    o.set_x(v->x), o.set_y(v->y), o.set_z(v->z);
    total += 24;  // mesh.proto: an origin counts 24 bytes
  }
  header.set_total_bytes(total);
}

// The body streams into UploadMesh in 64 KiB pieces; the server checks the header's size first,
// so a refused upload stops reading the body early. An OBJ file, or with topology_of the
// positions (and UVs) of a mesh whose topology a stored one has.
void uploadMesh(const HttpFrontDoor::Services& s, const httplib::Request& request, httplib::Response& response,
                const httplib::ContentReader& body) {
  const bool positionsOnly = request.has_param("topology_of");
  if (positionsOnly) {
    checkQueryParameters(request.params, {"id", "display_name", "topology_of", "uv_values", "origin"});
  } else {
    checkQueryParameters(request.params, {"id", "display_name"});
  }
  const std::string length = request.get_header_value("Content-Length");
  if (length.empty()) {
    return refuseBody(body, 411,
                      positionsOnly ? "an upload needs its Content-Length (4 bytes a float)"
                                    : "an upload needs its Content-Length (the OBJ file's size)",
                      response);
  }
  const int64_t bytes = std::atoll(length.c_str());
  if (positionsOnly && bytes % 4 != 0) {
    return refuseBody(body, 400,
                      fmt::format("the body: {} bytes is not a whole number of 4-byte floats (a positions-only "
                                  "upload sends little-endian float32 positions, then its UVs)",
                                  bytes),
                      response);
  }
  v1::UploadMeshRequest message;
  v1::UploadMeshHeader& header = *message.mutable_header();
  header.set_mesh_id(request.get_param_value("id"));
  header.set_display_name(request.get_param_value("display_name"));
  v1::UploadMeshRequest origin;
  int64_t positions = 0;
  if (positionsOnly) {
    positionsHeader(request, bytes, header, &origin, &positions);
  } else {
    header.set_format(v1::MESH_FORMAT_OBJ);
    header.set_total_bytes(bytes);
  }
  auto context = contextFor(request);
  v1::Mesh mesh;
  std::unique_ptr<grpc::ClientWriter<v1::UploadMeshRequest>> writer = s.meshes->UploadMesh(context.get(), &mesh);
  bool open = writer->Write(message);
  if (open && origin.has_arrays()) open = writer->Write(origin);
  std::string pending;
  FloatBody floats(positions);
  auto flush = [&] {
    if (positionsOnly) {
      open = open && writer->Write(floats.take());
      return;
    }
    message.set_obj_data(pending);
    open = open && writer->Write(message);
    pending.clear();
  };
  size_t drained = 0;
  body([&](const char* data, size_t size) {
    if (!open) return (drained += size) < kDrainBytes;  // refused: its status is in Finish()
    if (positionsOnly) {
      if (floats.append(data, size)) flush();
      return true;
    }
    pending.append(data, size);
    if (pending.size() >= kUploadChunkBytes) flush();
    return true;
  });
  if (open && (positionsOnly ? !floats.empty() : !pending.empty())) flush();
  if (open) writer->WritesDone();
  const grpc::Status status = writer->Finish();
  if (!status.ok()) return respondWithStatus(status, context.get(), response);
  copyRequestId(*context, response);
  response.set_header("Location", "/v1/" + mesh.name());
  respondWithJson(mesh, 201, response);
}

// A Tessellate call whose GLB is being streamed out: the first chunk is read before the response
// starts, so that a refusal is still an HTTP status; what follows goes out as it arrives.
struct GlbStream {
  std::unique_ptr<grpc::ClientContext> context;
  std::unique_ptr<grpc::ClientReader<v1::TessellateResponse>> reader;
  std::string pending;
  bool finished = false;

  // Reads up to the next GLB bytes; false at the end of the stream.
  bool next() {
    v1::TessellateResponse message;
    while (reader->Read(&message)) {
      if (message.has_glb_chunk()) {
        pending = message.glb_chunk().data();
        return true;
      }
    }
    return false;
  }
  grpc::Status finish() {
    finished = true;
    return reader->Finish();
  }
};

// Strong: the GLB is a function of the mesh's content, the request and the server's version.
std::string glbEntityTag(const std::string& version, const std::string& meshSha256, const v1::TessellateRequest& request) {
  std::string canonical;
  google::protobuf::io::StringOutputStream out(&canonical);
  {
    google::protobuf::io::CodedOutputStream coded(&out);
    coded.SetSerializationDeterministic(true);
    request.SerializeToCodedStream(&coded);
  }
  return fmt::format("\"{}\"", sha256Hex(fmt::format("{}\n{}\n{}", version, meshSha256, canonical)));
}

bool matchesEntityTag(const std::string& ifNoneMatch, const std::string& tag) {
  if (ifNoneMatch == "*") return true;
  return ifNoneMatch.find(tag) != std::string::npos;
}

void tessellation(const HttpFrontDoor::Services& s, const httplib::Request& request, httplib::Response& response) {
  const std::string id = request.matches[1];
  const v1::TessellateRequest tessellate = tessellateRequestFromQuery(id, request.params);
  auto lookup = contextFor(request);
  v1::GetMeshRequest get;
  get.set_name(tessellate.name());
  v1::Mesh mesh;
  if (grpc::Status status = s.meshes->GetMesh(lookup.get(), get, &mesh); !status.ok()) {
    return respondWithStatus(status, lookup.get(), response);
  }
  const std::string tag = glbEntityTag(s.options.version, mesh.sha256(), tessellate);
  response.set_header("ETag", tag);
  response.set_header("Cache-Control", "no-cache");
  if (request.has_header("If-None-Match") && matchesEntityTag(request.get_header_value("If-None-Match"), tag)) {
    copyRequestId(*lookup, response);  // the GetMesh that answered it is the request's one call
    response.status = 304;
    return;
  }
  auto stream = std::make_shared<GlbStream>();
  stream->context = contextFor(request);
  stream->reader = s.tessellation->Tessellate(stream->context.get(), tessellate);
  if (!stream->next()) {
    grpc::Status status = stream->finish();
    if (status.ok()) status = grpc::Status(grpc::StatusCode::INTERNAL, "the tessellation ended without a GLB");
    return respondWithStatus(status, stream->context.get(), response);
  }
  copyRequestId(*stream->context, response);
  response.set_header("Content-Disposition", fmt::format("inline; filename=\"{}.glb\"", id));
  response.set_chunked_content_provider(
      "model/gltf-binary",
      [stream](size_t, httplib::DataSink& sink) {
        if (!stream->pending.empty() && !sink.write(stream->pending.data(), stream->pending.size())) return false;
        stream->pending.clear();
        if (stream->next()) return true;
        const grpc::Status status = stream->finish();
        if (!status.ok()) {
          spdlog::warn("http GLB stream ended early: {}", status.error_message());
          return false;  // the client sees a truncated chunked body, never a wrong GLB
        }
        sink.done();
        return true;
      },
      [stream](bool) {
        if (!stream->finished) {
          stream->context->TryCancel();  // the client went away
          stream->finish();
        }
      });
}

void frame(const HttpFrontDoor::Services& s, const httplib::Request& request, httplib::Response& response) {
  const std::string id = request.matches[1];
  const bool png = std::string(request.matches[2]) == "png";
  const v1::RenderRequest render =
      renderRequestFromQuery(id, request.params, png ? v1::IMAGE_FORMAT_PNG : v1::IMAGE_FORMAT_JPEG);
  auto context = contextFor(request);
  std::unique_ptr<grpc::ClientReader<v1::RenderResponse>> reader = s.render->Render(context.get(), render);
  std::string image;
  v1::RenderResponse message;
  while (reader->Read(&message)) {
    if (message.has_chunk()) image += message.chunk().data();
  }
  const grpc::Status status = reader->Finish();
  if (!status.ok()) return respondWithStatus(status, context.get(), response);
  copyRequestId(*context, response);
  response.set_content(image, png ? "image/png" : "image/jpeg");
}

// The viewer: its page at /, its scripts and three.js under /web/ (static files, no listing).
void addViewer(const std::string& root, httplib::Server& http) {
  const bool present = !root.empty() && std::filesystem::is_regular_file(std::filesystem::path(root) / "index.html");
  if (present) http.set_mount_point("/web", root);
  http.Get("/", [root, present](const httplib::Request&, httplib::Response& response) {
    if (!present) {
      response.status = 404;
      response.set_content(errorJson(grpc::Status(grpc::StatusCode::NOT_FOUND,
                                                   fmt::format("no web viewer at --http-web-root \"{}\" (it is built "
                                                               "into build/web when npm is present)",
                                                               quoteForMessage(root)))),
                           "application/json");
      return;
    }
    std::ifstream page(std::filesystem::path(root) / "index.html", std::ios::binary);
    response.set_content(std::string(std::istreambuf_iterator<char>(page), {}), "text/html; charset=utf-8");
  });
}

void addCors(const std::string& origin, httplib::Server& http) {
  if (origin.empty()) return;
  http.set_post_routing_handler([origin](const httplib::Request&, httplib::Response& response) {
    response.set_header("Access-Control-Allow-Origin", origin);
    response.set_header("Access-Control-Expose-Headers", "ETag, Retry-After, X-Request-Id, Location");
    if (origin != "*") response.set_header("Vary", "Origin");
  });
  http.Options(R"(/v1/.*)", [](const httplib::Request&, httplib::Response& response) {
    response.status = 204;
    response.set_header("Access-Control-Allow-Methods", "GET, POST, DELETE, OPTIONS");
    response.set_header("Access-Control-Allow-Headers", "Authorization, Content-Type, If-None-Match, X-Request-Id");
    response.set_header("Access-Control-Max-Age", "600");
  });
}

}  // namespace

HttpFrontDoor::HttpFrontDoor(HttpFrontDoorOptions options, std::shared_ptr<grpc::Channel> channel)
    : listener_(options.listen, "--http-listen"), services_(std::make_unique<Services>()) {
  services_->options = std::move(options);
  services_->meshes = v1::MeshService::NewStub(channel);
  services_->tessellation = v1::TessellationService::NewStub(channel);
  services_->render = v1::RenderService::NewStub(channel);
  const Services& s = *services_;
  httplib::Server& http = listener_.routes();
  const std::string mesh = R"(/v1/meshes/([A-Za-z0-9._~-]+))";
  http.Get("/v1/meshes", guarded([&s](auto& rq, auto& rs) { listMeshes(s, rq, rs); }));
  http.Post("/v1/meshes", [&s](const httplib::Request& rq, httplib::Response& rs, const httplib::ContentReader& body) {
    guarded([&](auto& q, auto& r) { uploadMesh(s, q, r, body); })(rq, rs);
  });
  http.Get(mesh, guarded([&s](auto& rq, auto& rs) { getMesh(s, rq, rs); }));
  http.Delete(mesh, guarded([&s](auto& rq, auto& rs) { deleteMesh(s, rq, rs); }));
  http.Get(mesh + "/tessellation\\.glb", guarded([&s](auto& rq, auto& rs) { tessellation(s, rq, rs); }));
  http.Get(mesh + "/frame\\.(png|jpg)", guarded([&s](auto& rq, auto& rs) { frame(s, rq, rs); }));
  addViewer(s.options.webRoot, http);
  addCors(s.options.corsOrigin, http);
  http.set_error_handler([](const httplib::Request& request, httplib::Response& response) {
    if (!response.body.empty()) return;
    const grpc::StatusCode code = response.status == 404 ? grpc::StatusCode::NOT_FOUND : grpc::StatusCode::INVALID_ARGUMENT;
    response.set_content(errorJson(grpc::Status(code, fmt::format("{} {}: no such endpoint (see server/README.md, HTTP)",
                                                                  request.method, quoteForMessage(request.path)))),
                         "application/json");
  });
}

HttpFrontDoor::~HttpFrontDoor() { stop(); }

}  // namespace tessera::server
