// tessera-idle-streams: what idle streams do to everyone else's calls (issue: hostile clients).
// Against a running server, measures the latency of authenticated GetMesh calls three times:
// with nothing else open; while --streams UploadMesh streams without the token are held open and
// silent (each refused as it arrives); and while as many streams with the token are held open and
// silent (past --max-open-streams the server refuses them; the rest wait for the idle timeout).
//
//   tessera-idle-streams --server 127.0.0.1:PORT --token T --mesh meshes/NAME [--streams 600]
//       [--calls 2000]
#include <grpcpp/grpcpp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "tessera/v1/mesh.grpc.pb.h"

namespace {

namespace v1 = tessera::v1;
using Clock = std::chrono::steady_clock;

struct HeldStream {
  grpc::ClientContext context;
  v1::Mesh response;
  std::unique_ptr<grpc::ClientWriter<v1::UploadMeshRequest>> writer;
};

void authorize(grpc::ClientContext& context, const std::string& token) {
  if (!token.empty()) context.AddMetadata("authorization", "Bearer " + token);
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
}

// Each on a channel of its own, as separate clients would be.
std::vector<std::unique_ptr<HeldStream>> holdStreams(const std::string& server, int count, const std::string& token) {
  std::vector<std::unique_ptr<HeldStream>> held;
  for (int i = 0; i < count; ++i) {
    auto channel = grpc::CreateChannel(server, grpc::InsecureChannelCredentials());
    auto stub = v1::MeshService::NewStub(channel);
    auto stream = std::make_unique<HeldStream>();
    authorize(stream->context, token);
    stream->writer = stub->UploadMesh(&stream->context, &stream->response);
    held.push_back(std::move(stream));
  }
  return held;
}

struct Latencies {
  int failed = 0;
  double p50 = 0, p99 = 0, max = 0;
};

Latencies measure(v1::MeshService::Stub& stub, const std::string& token, const std::string& mesh, int calls) {
  std::vector<double> ms;
  Latencies out;
  for (int i = 0; i < calls; ++i) {
    grpc::ClientContext context;
    authorize(context, token);
    v1::GetMeshRequest request;
    request.set_name(mesh);
    v1::Mesh response;
    const auto start = Clock::now();
    const grpc::Status status = stub.GetMesh(&context, request, &response);
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    out.failed += !status.ok();
  }
  std::sort(ms.begin(), ms.end());
  out.p50 = ms[ms.size() / 2];
  out.p99 = ms[std::min(ms.size() - 1, ms.size() * 99 / 100)];
  out.max = ms.back();
  return out;
}

void row(const char* what, const Latencies& l) {
  std::printf("| %s | %d | %.2f | %.2f | %.2f |\n", what, l.failed, l.p50, l.p99, l.max);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Latency of authenticated calls while idle streams are held open"};
  std::string server, token, mesh;
  int streams = 600, calls = 2000;
  app.add_option("--server", server, "HOST:PORT")->required();
  app.add_option("--token", token, "The server's bearer token")->required();
  app.add_option("--mesh", mesh, "A stored mesh, meshes/NAME")->required();
  app.add_option("--streams", streams, "Idle streams to hold")->capture_default_str();
  app.add_option("--calls", calls, "GetMesh calls per measurement")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  auto stub = v1::MeshService::NewStub(grpc::CreateChannel(server, grpc::InsecureChannelCredentials()));
  std::printf("| held open | failed calls | p50 ms | p99 ms | max ms |\n|---|---:|---:|---:|---:|\n");
  row("nothing", measure(*stub, token, mesh, calls));
  {
    auto strangers = holdStreams(server, streams, "");
    row((std::to_string(streams) + " streams without the token").c_str(), measure(*stub, token, mesh, calls));
    for (auto& s : strangers) s->context.TryCancel();
  }
  {
    auto owners = holdStreams(server, streams, token);
    row((std::to_string(streams) + " streams with the token").c_str(), measure(*stub, token, mesh, calls));
    for (auto& s : owners) s->context.TryCancel();
  }
  return 0;
}
