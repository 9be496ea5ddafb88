// The calls `tessera bench` makes: one request of a kind (tessellate, get, list, info; upload for
// the cold mix) on a channel, with a deadline, measured in the protobuf bytes it moved and judged
// by its status. A tessellation counts as successful only when its stream is complete and
// consistent (contiguous offsets, the summary's size and, unless turned off, its SHA-256).
#pragma once

#include <grpcpp/grpcpp.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "client/remote_connection.h"
#include "client/remote_upload.h"
#include "tessera/v1/mesh.grpc.pb.h"
#include "tessera/v1/server_info.grpc.pb.h"
#include "tessera/v1/tessellation.grpc.pb.h"

namespace tessera::cli {

enum class BenchOp { kTessellate, kGet, kList, kInfo, kUpload };
// The operations a mix may name. Uploads come only from the cold mix, whose every upload is a
// mesh of its own (remote_bench_cold.h).
inline constexpr BenchOp kMixOps[] = {BenchOp::kTessellate, BenchOp::kGet, BenchOp::kList,
                                      BenchOp::kInfo};

std::string_view benchOpName(BenchOp op);
// One of kMixOps by name.
std::optional<BenchOp> mixOpFromName(std::string_view name);

// What one call came to.
struct CallOutcome {
  grpc::StatusCode code = grpc::StatusCode::OK;
  // The status was OK but the stream was unusable (truncated, out of order, wrong checksum).
  bool badStream = false;
  int64_t bytesSent = 0;      // serialized request messages
  int64_t bytesReceived = 0;  // serialized response messages
  // Tessellate: the stage timings the server reports in its summary, added up (the computation
  // without queueing and transfer); negative for other calls.
  double serverSeconds = -1;
  // The server's grpc-retry-pushback-ms on a refusal (it is busy: retry no sooner); 0 if none.
  int64_t retryAfterMs = 0;
  bool ok() const { return code == grpc::StatusCode::OK && !badStream; }
  // A gRPC status code name ("RESOURCE_EXHAUSTED"), or "BAD_STREAM"; "OK" when ok().
  std::string errorName() const;
};

// The requests a run sends, built once: one TessellateRequest and one GetMeshRequest per mesh.
struct BenchRequests {
  std::vector<tessera::v1::TessellateRequest> tessellate;
  std::vector<tessera::v1::GetMeshRequest> get;
  tessera::v1::ListMeshesRequest list;
  bool verifyChecksum = true;
  std::chrono::milliseconds timeout{60'000};  // deadline of every call
};

// Stubs on one channel; call() is safe to use from one thread at a time per client.
class BenchClient {
 public:
  BenchClient(std::shared_ptr<grpc::Channel> channel, const RemoteEndpoint& endpoint,
              const BenchRequests& requests);

  // One of kMixOps; sequence picks the mesh (round robin over the meshes of the run).
  CallOutcome call(BenchOp op, uint64_t sequence);
  CallOutcome tessellate(const tessera::v1::TessellateRequest& request);
  // An ARRAYS upload as meshes/<options.meshId>.
  CallOutcome upload(const tessera::v1::MeshArrays& arrays, const UploadOptions& options);

 private:
  void prepare(grpc::ClientContext& context) const;

  const RemoteEndpoint& endpoint_;
  const BenchRequests& requests_;
  std::unique_ptr<tessera::v1::MeshService::Stub> meshes_;
  std::unique_ptr<tessera::v1::TessellationService::Stub> tessellation_;
  std::unique_ptr<tessera::v1::ServerInfoService::Stub> info_;
};

}  // namespace tessera::cli
