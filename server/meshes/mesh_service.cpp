#include "server/meshes/mesh_service.h"

#include <fmt/format.h>

#include <algorithm>
#include <memory>

#include "server/calls/call_guard.h"
#include "server/calls/memory_release.h"
#include "server/meshes/mesh_names.h"
#include "server/meshes/mesh_proto.h"
#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

constexpr int kDefaultPageSize = 50;
constexpr int kMaxPageSize = 1000;
// Well under gRPC's 4 MiB message limit, and big enough that per-message overhead is small.
constexpr size_t kDownloadChunkBytes = 64 * 1024;
// Uploads up to this size take the light lane (admission_control.h).
constexpr int64_t kLightUploadBytes = 4 << 20;

}  // namespace

void MeshServiceImpl::receive(Watched<grpc::ServerReader<v1::UploadMeshRequest>>& reader,
                              UploadAssembler& upload) {
  v1::UploadMeshRequest message;
  while (reader.Read(&message)) {
    const int64_t before = upload.receivedBytes();
    const bool isHeader = !upload.hasHeader();
    upload.accept(message);
    metrics_.uploadBytes.add({}, static_cast<double>(upload.receivedBytes() - before));
    // Refuse a taken id before the client sends megabytes; create() checks again atomically.
    if (isHeader && repository_.exists(upload.meshId())) {
      throwStatus(grpc::StatusCode::ALREADY_EXISTS,
                  fmt::format("mesh {} already exists", meshName(upload.meshId())));
    }
    // Likewise a positions-only upload of a mesh that is not there; finish() looks again.
    if (isHeader && !upload.topologyOfId().empty()) topologyOf(upload.topologyOfId());
  }
}

std::shared_ptr<const ControlMesh> MeshServiceImpl::topologyOf(const std::string& id) {
  if (!repository_.exists(id)) {
    throwStatus(grpc::StatusCode::NOT_FOUND,
                fmt::format("header.topology_of: mesh {} not found; a positions-only upload takes its "
                            "topology from a stored mesh",
                            meshName(id)));
  }
  return repository_.mesh(repository_.metadata(id));
}

grpc::Status MeshServiceImpl::UploadMesh(grpc::ServerContext* context,
                                         grpc::ServerReader<v1::UploadMeshRequest>* reader,
                                         v1::Mesh* response) {
  const ReleaseMemoryOnExit release;  // the upload's buffers and parse, after the call
  return guardCall(*context, auth_, [&] {
    CancellationToken cancel = cancellationFor(*context);
    UploadAssembler upload(limits_);
    {
      StreamWatch::Call call = streams_.open(*context, "UploadMesh");
      Watched watched(*reader, call);
      receive(watched, upload);
    }
    // Read() also returns false when the client cancels or the deadline passes: that is not the
    // end of a complete upload.
    cancel.throwIfCancelled();
    // Parsing and validating is the CPU-heavy part; receiving is not, so it waits outside. A
    // small upload is short (armorguy's 1.3 MB OBJ parses and validates in well under a second),
    // so it takes the light lane and is never queued behind long tessellations.
    // A positions-only upload whose topology is not kept yet builds it (Far's refinement), which
    // is no short job.
    std::shared_ptr<const ControlMesh> topology;
    bool keepTopology = false;
    if (!upload.topologyOfId().empty()) {
      topology = topologyOf(upload.topologyOfId());
      keepTopology = !patches_.holdsTopology(*topology);
    }
    const AdmissionLane lane = upload.receivedBytes() <= kLightUploadBytes && !keepTopology
                                   ? AdmissionLane::kLight
                                   : AdmissionLane::kMain;
    AdmissionControl::Slot slot = admission_.acquire(cancel, {}, 0, "the upload", lane);
    AssembledUpload assembled = upload.finish(topology.get());
    topology.reset();
    admission_.requireFits(assembled.preprocessingBytes, assembled.where + "preprocessing the mesh");
    cancel.throwIfCancelled();
    // An upload that names the topology it shares is an edit, and more are likely to follow: the
    // topology is kept so that this mesh's first tessellation, and the next edits', only refine
    // their positions (server/README.md, Caches). Before the mesh is stored, so that a cancelled
    // call leaves nothing. A mesh the topology cannot be built for, or no memory for it now, is
    // stored all the same: its Tessellate says what a full upload's would.
    if (keepTopology) {
      try {
        patches_.keepTopology(assembled.mesh, cancel, &slot);
      } catch (const TesseraError&) {
      } catch (const StatusError& error) {
        if (error.code() != grpc::StatusCode::RESOURCE_EXHAUSTED) throw;
      }
    }
    MeshMetadata stored = repository_.create(std::move(assembled.mesh), std::move(assembled.metadata));
    toProto(stored, response);
    metrics_.notes.note(context, "mesh", stored.id);
    metrics_.notes.note(context, "bytes", int64_t(upload.receivedBytes()));
    if (!upload.topologyOfId().empty()) metrics_.notes.note(context, "topology_of", meshName(upload.topologyOfId()));
  });
}

grpc::Status MeshServiceImpl::GetMesh(grpc::ServerContext* context, const v1::GetMeshRequest* request,
                                      v1::Mesh* response) {
  return guardCall(*context, auth_, [&] {
    std::string id = meshIdFromName(request->name(), "name");
    toProto(repository_.metadata(id), response);
  });
}

grpc::Status MeshServiceImpl::ListMeshes(grpc::ServerContext* context,
                                         const v1::ListMeshesRequest* request,
                                         v1::ListMeshesResponse* response) {
  return guardCall(*context, auth_, [&] {
    if (request->page_size() < 0) {
      throwInvalidArgument(fmt::format("page_size: must not be negative (got {})", request->page_size()));
    }
    int pageSize = request->page_size() == 0 ? kDefaultPageSize
                                             : std::min(request->page_size(), kMaxPageSize);
    std::string after = request->page_token().empty() ? "" : decodePageToken(request->page_token());
    // One extra row tells whether another page follows without a second query.
    std::vector<MeshMetadata> page = repository_.list(after, pageSize + 1);
    bool more = static_cast<int>(page.size()) > pageSize;
    if (more) page.resize(pageSize);
    for (const MeshMetadata& m : page) toProto(m, response->add_meshes());
    if (more) response->set_next_page_token(encodePageToken(page.back().id));
  });
}

grpc::Status MeshServiceImpl::DeleteMesh(grpc::ServerContext* context,
                                         const v1::DeleteMeshRequest* request,
                                         google::protobuf::Empty*) {
  return guardCall(*context, auth_, [&] {
    repository_.remove(meshIdFromName(request->name(), "name"));
  });
}

grpc::Status MeshServiceImpl::DownloadMesh(grpc::ServerContext* context,
                                           const v1::DownloadMeshRequest* request,
                                           grpc::ServerWriter<v1::DownloadMeshResponse>* writer) {
  return guardCall(*context, auth_, [&] {
    MeshMetadata metadata = repository_.metadata(meshIdFromName(request->name(), "name"));
    std::shared_ptr<const ControlMesh> mesh = repository_.mesh(metadata);
    CancellationToken cancel = cancellationFor(*context);
    StreamWatch::Call call = streams_.open(*context, "DownloadMesh");
    Watched watched(*writer, call);
    v1::DownloadMeshResponse first;
    toProto(metadata, first.mutable_mesh());
    if (!watched.Write(first)) throw OperationCancelled();
    bool complete = forEachArraysChunk(*mesh, kDownloadChunkBytes, [&](const v1::MeshArrays& chunk) {
      if (cancel.cancelled()) return false;
      v1::DownloadMeshResponse message;
      *message.mutable_arrays() = chunk;
      return watched.Write(message);
    });
    if (!complete) throw OperationCancelled();
  });
}

}  // namespace tessera::server
