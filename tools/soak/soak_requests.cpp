#include "tools/soak/soak_requests.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

#include "client/remote_upload.h"

namespace tessera::soak {

namespace {

using Clock = std::chrono::steady_clock;
using Code = grpc::StatusCode;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The server's pushback hint (grpc-retry-pushback-ms) on a refused call, or -1.
int64_t pushbackMs(const grpc::ClientContext& context) {
  const auto& trailers = context.GetServerTrailingMetadata();
  const auto hint = trailers.find("grpc-retry-pushback-ms");
  if (hint == trailers.end()) return -1;
  return std::atoll(std::string(hint->second.data(), hint->second.size()).c_str());
}

struct Attempt {
  grpc::Status status;
  int64_t pushback = -1;
};

// A Tessellate call read to its end (the GLB's chunks counted, not kept). With abandonAfter > 0
// the client cancels the call after that many messages, as one that walks away would.
Attempt tessellate(SoakClient& client, const std::string& token, const v1::TessellateRequest& request,
                   double deadlineSeconds, int abandonAfter = 0) {
  grpc::ClientContext context;
  prepare(context, token, deadlineSeconds);
  auto reader = client.tessellation->Tessellate(&context, request);
  v1::TessellateResponse message;
  for (int read = 0; reader->Read(&message);) {
    if (abandonAfter > 0 && ++read >= abandonAfter) {
      context.TryCancel();
      break;
    }
  }
  Attempt attempt{reader->Finish()};
  attempt.pushback = pushbackMs(context);
  return attempt;
}

Attempt render(SoakClient& client, const std::string& token, const v1::RenderRequest& request, double deadlineSeconds) {
  grpc::ClientContext context;
  prepare(context, token, deadlineSeconds);
  auto reader = client.render->Render(&context, request);
  v1::RenderResponse message;
  while (reader->Read(&message)) {
  }
  Attempt attempt{reader->Finish()};
  attempt.pushback = pushbackMs(context);
  return attempt;
}

Attempt getMesh(SoakClient& client, const std::string& token, const std::string& name) {
  grpc::ClientContext context;
  prepare(context, token, 30);
  v1::GetMeshRequest request;
  request.set_name(name);
  v1::Mesh mesh;
  return {client.meshes->GetMesh(&context, request, &mesh)};
}

v1::TessellateRequest relativeRequest(const std::string& mesh, double relative) {
  v1::TessellateRequest request;
  request.set_name(mesh);
  request.set_relative(relative);
  return request;
}

v1::RenderRequest frameRequest(const std::string& mesh, const v1::Camera& camera, int width, int height,
                               v1::ImageFormat format) {
  v1::RenderRequest request;
  request.set_name(mesh);
  v1::Camera* view = request.add_cameras();
  *view = camera;
  view->set_width(width);
  view->set_height(height);
  request.mutable_settings()->set_format(format);
  return request;
}

Outcome finish(std::string kind, Role role, const Attempt& last, Clock::time_point start,
               std::initializer_list<Code> expected) {
  Outcome out;
  out.kind = std::move(kind);
  out.role = role;
  out.code = last.status.error_code();
  out.message = last.status.error_message();
  out.ms = msSince(start);
  // Any call may be pushed back while the server is busy.
  out.pushedBack = out.code == Code::RESOURCE_EXHAUSTED && last.pushback >= 0;
  out.expected = out.pushedBack || std::find(expected.begin(), expected.end(), out.code) != expected.end();
  return out;
}

// A normal call made again after each pushback (waiting the hinted time) while `budget` seconds
// from the start allow; a call refused without a hint is not retried.
template <typename Call>
Outcome withRetries(const std::string& kind, double budgetSeconds, Call call) {
  const auto start = Clock::now();
  Attempt attempt;
  int pushbacks = 0;
  for (;;) {
    attempt = call(std::max(1.0, budgetSeconds - msSince(start) / 1000));
    if (attempt.status.error_code() != Code::RESOURCE_EXHAUSTED || attempt.pushback < 0) break;
    const double waitMs = double(std::max<int64_t>(attempt.pushback, 10));
    if (msSince(start) + waitMs > budgetSeconds * 1000) break;
    ++pushbacks;
    std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(waitMs));
  }
  Outcome out = finish(kind, Role::kNormal, attempt, start, {Code::OK});
  out.pushbacks = pushbacks;
  return out;
}

// Removes meshes/id; best effort (a mesh left behind costs only store space).
void deleteMesh(SoakClient& client, const std::string& token, const std::string& id) {
  grpc::ClientContext context;
  prepare(context, token, 30);
  v1::DeleteMeshRequest request;
  request.set_name("meshes/" + id);
  google::protobuf::Empty empty;
  client.meshes->DeleteMesh(&context, request, &empty);
}

// Refused or cut short by the server's own limits: what any heavy request may end with.
constexpr std::initializer_list<Code> kHeavy = {Code::OK, Code::RESOURCE_EXHAUSTED, Code::DEADLINE_EXCEEDED};

Outcome creasedUpload(SoakClient& client, const SoakSetup& setup, const std::string& id) {
  const auto start = Clock::now();
  Attempt attempt;
  {
    grpc::ClientContext context;
    attempt.status = uploadObj(*client.meshes, context, setup.token, id, creasedEverywhere(setup.smallObj), 120);
    attempt.pushback = pushbackMs(context);
  }
  if (attempt.status.ok()) {
    // Accepted: tessellate it under a deadline, then remove it.
    attempt = tessellate(client, setup.token, relativeRequest("meshes/" + id, 1e-2), 60);
    deleteMesh(client, setup.token, id);
  }
  return finish("creased upload", Role::kHostile, attempt, start, kHeavy);
}

Outcome malformedUpload(SoakClient& client, const SoakSetup& setup, const std::string& id) {
  const auto start = Clock::now();
  // A face naming vertex 99 of a three-vertex mesh.
  grpc::ClientContext context;
  const Attempt attempt{uploadObj(*client.meshes, context, setup.token, id, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n", 30),
                        pushbackMs(context)};
  return finish("malformed upload", Role::kHostile, attempt, start, {Code::INVALID_ARGUMENT});
}

// A cold call ends well when it succeeds, or when the server refuses it for memory saying why
// (a pushback has been waited out by then).
Outcome asCold(Outcome out) {
  out.role = Role::kCold;
  out.expected = out.code == Code::OK || (out.code == Code::RESOURCE_EXHAUSTED && !out.message.empty());
  return out;
}

// Copies of different seeds, clients and serials never share content.
uint64_t copyNumber(int seed, int clientIndex, uint64_t serial) {
  return (uint64_t(seed) << 40) + (uint64_t(clientIndex) << 32) + serial;
}

}  // namespace

void prepare(grpc::ClientContext& context, const std::string& token, double seconds) {
  if (!token.empty()) context.AddMetadata("authorization", "Bearer " + token);
  context.set_deadline(std::chrono::system_clock::now() +
                       std::chrono::milliseconds(int64_t(seconds * 1000)));
}

SoakClient::SoakClient(const std::shared_ptr<grpc::Channel>& channel)
    : meshes(v1::MeshService::NewStub(channel)),
      tessellation(v1::TessellationService::NewStub(channel)),
      render(v1::RenderService::NewStub(channel)) {}

Outcome normalRequest(SoakClient& client, const SoakSetup& setup) {
  const int choice = int(client.random() % (setup.renderAvailable ? 10 : 8));
  const std::string& token = setup.token;
  if (choice < 4) {
    return withRetries("tessellate 1e-2", 60, [&](double seconds) {
      return tessellate(client, token, relativeRequest(setup.smallMesh, 1e-2), seconds);
    });
  }
  if (choice < 6) {
    return withRetries("tessellate 1e-3", 60, [&](double seconds) {
      return tessellate(client, token, relativeRequest(setup.smallMesh, 1e-3), seconds);
    });
  }
  if (choice < 8) {
    return withRetries("get mesh", 30, [&](double) { return getMesh(client, token, setup.smallMesh); });
  }
  return withRetries("frame 256x256", 60, [&](double seconds) {
    return render(client, token, frameRequest(setup.smallMesh, setup.smallView, 256, 256, v1::IMAGE_FORMAT_PNG), seconds);
  });
}

void warmUp(SoakClient& client, const SoakSetup& setup) {
  for (const std::string& mesh : {setup.smallMesh, setup.largeMesh}) {
    const Outcome done = withRetries("warm-up", 300, [&](double seconds) {
      return tessellate(client, setup.token, relativeRequest(mesh, 1e-2), seconds);
    });
    if (done.code != Code::OK) throw std::runtime_error("tessellating " + mesh + ": " + done.message);
  }
}

Outcome hostileRequest(SoakClient& client, const SoakSetup& setup, int clientIndex, uint64_t serial, bool runaway) {
  const std::string id = "soak-" + std::to_string(clientIndex) + "-" + std::to_string(serial);
  const std::string& token = setup.token;
  const auto start = Clock::now();
  const uint32_t kinds = setup.renderAvailable ? 9 : 8;
  switch (runaway ? 7 : client.random() % kinds) {
    case 0:
      return creasedUpload(client, setup, id);
    case 1: {
      v1::TessellateRequest request;
      request.set_name(setup.largeMesh);
      request.set_uniform_level(40);
      return finish("uniform level 40", Role::kHostile, tessellate(client, token, request, 120), start, kHeavy);
    }
    case 2:
      return finish("relative 1e-5", Role::kHostile,
                    tessellate(client, token, relativeRequest(setup.largeMesh, 1e-5), 120), start, kHeavy);
    case 3:
      return malformedUpload(client, setup, id);
    case 4:
      return finish("tolerance NaN", Role::kHostile,
                    tessellate(client, token, relativeRequest(setup.smallMesh, std::nan("")), 30), start,
                    {Code::INVALID_ARGUMENT});
    case 5:
      // A heavy call whose client gives it 50 ms.
      return finish("overdue 1e-4", Role::kHostile,
                    tessellate(client, token, relativeRequest(setup.smallMesh, 1e-4), 0.05), start, kHeavy);
    case 6:
      // The client reads the first message and walks away.
      return finish("abandoned 1e-3", Role::kHostile,
                    tessellate(client, token, relativeRequest(setup.largeMesh, 1e-3), 120, 1), start,
                    {Code::CANCELLED, Code::OK, Code::RESOURCE_EXHAUSTED});
    case 7:
      // Legitimate but long (bigguy at 1e-5: 2 M triangles, seconds under load, within a 3 GiB
      // budget), bounded by its client's deadline: the server must stop it then (issue 47).
      return finish(kRunaway, Role::kHostile, tessellate(client, token, relativeRequest(setup.smallMesh, 1e-5), 1),
                    start, {Code::DEADLINE_EXCEEDED, Code::RESOURCE_EXHAUSTED});
    default:
      return finish("frame 8192x8192 raw", Role::kHostile,
                    render(client, token,
                           frameRequest(setup.smallMesh, setup.smallView, 8192, 8192, v1::IMAGE_FORMAT_RAW_RGBA), 120),
                    start, kHeavy);
  }
}

Outcome lastRunaway(SoakClient& client, const SoakSetup& setup) {
  const auto start = Clock::now();
  return finish(kLastRunaway, Role::kHostile, tessellate(client, setup.token, relativeRequest(setup.smallMesh, 1e-5), 0.3),
                start, {Code::DEADLINE_EXCEEDED});
}

std::vector<Outcome> coldRequest(SoakClient& client, const SoakSetup& setup, int clientIndex, uint64_t serial) {
  const cli::ColdSource& source = setup.coldSources[(size_t(clientIndex) + serial) % setup.coldSources.size()];
  const v1::MeshArrays copy = cli::coldCopy(source, copyNumber(setup.seed, clientIndex, serial));
  cli::UploadOptions options;
  options.meshId = "soak-cold-" + std::to_string(clientIndex) + "-" + std::to_string(serial);
  options.subdivision = source.options;
  std::string sha256;
  std::vector<Outcome> outcomes{asCold(withRetries("cold upload", 120, [&](double seconds) {
    grpc::ClientContext context;
    prepare(context, setup.token, seconds);
    v1::Mesh mesh;
    Attempt attempt{cli::uploadMeshArrays(*client.meshes, context, copy, options, &mesh)};
    attempt.pushback = pushbackMs(context);
    sha256 = mesh.sha256();
    return attempt;
  }))};
  if (outcomes.back().code != Code::OK) return outcomes;
  outcomes.back().sha256 = sha256;
  outcomes.push_back(asCold(withRetries("cold first GLB", 120, [&](double seconds) {
    return tessellate(client, setup.token, relativeRequest("meshes/" + options.meshId, setup.coldTolerance), seconds);
  })));
  deleteMesh(client, setup.token, options.meshId);
  return outcomes;
}

std::string creasedEverywhere(const std::string& objText) {
  std::set<std::pair<int, int>> edges;
  std::istringstream lines(objText);
  std::string line;
  int vertices = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("v ", 0) == 0) ++vertices;
    if (line.rfind("f ", 0) != 0) continue;
    std::istringstream tokens(line.substr(2));
    std::vector<int> face;
    for (std::string token; tokens >> token;) {
      const int index = std::stoi(token.substr(0, token.find('/')));
      face.push_back(index < 0 ? vertices + index : index - 1);
    }
    for (size_t k = 0; k < face.size(); ++k) {
      const int a = face[k], b = face[(k + 1) % face.size()];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  }
  std::string out = objText;
  for (const auto& [a, b] : edges) out += "t crease 2/1/0 " + std::to_string(a) + " " + std::to_string(b) + " 9.5\n";
  return out;
}

grpc::Status uploadObj(v1::MeshService::Stub& stub, grpc::ClientContext& context, const std::string& token,
                       const std::string& id, const std::string& text, int deadlineSeconds) {
  prepare(context, token, deadlineSeconds);
  v1::Mesh mesh;
  auto writer = stub.UploadMesh(&context, &mesh);
  v1::UploadMeshRequest header;
  header.mutable_header()->set_mesh_id(id);
  header.mutable_header()->set_format(v1::MESH_FORMAT_OBJ);
  header.mutable_header()->set_total_bytes(int64_t(text.size()));
  bool sent = writer->Write(header);
  constexpr size_t kChunk = 64 * 1024;
  for (size_t at = 0; sent && at < text.size(); at += kChunk) {
    v1::UploadMeshRequest chunk;
    chunk.set_obj_data(text.substr(at, kChunk));
    sent = writer->Write(chunk);
  }
  writer->WritesDone();
  return writer->Finish();
}

}  // namespace tessera::soak
