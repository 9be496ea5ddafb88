// tessera.v1.MeshService: upload, get, list, delete and download of control meshes. A thin
// translation layer: the protocol checks live in UploadAssembler, storage in MeshRepository.
#pragma once

#include "server/calls/admission_control.h"
#include "server/calls/bearer_auth.h"
#include "server/meshes/mesh_repository.h"
#include "server/meshes/mesh_upload.h"
#include "server/meshes/patch_set_cache.h"
#include "server/operations/server_metrics.h"
#include "server/calls/stream_watch.h"
#include "tessera/v1/mesh.grpc.pb.h"

namespace tessera::server {

class MeshServiceImpl final : public tessera::v1::MeshService::Service {
 public:
  // patches: where a positions-only upload keeps its topology for the new mesh's first
  // tessellation (patch_set_cache.h, keepTopology).
  MeshServiceImpl(MeshRepository& repository, AdmissionControl& admission, StreamWatch& streams,
                  const BearerAuth& auth, const UploadLimits& limits, ServerMetrics& metrics,
                  PatchSetCache& patches)
      : repository_(repository), admission_(admission), streams_(streams), auth_(auth), limits_(limits),
        metrics_(metrics), patches_(patches) {}

  grpc::Status UploadMesh(grpc::ServerContext* context,
                          grpc::ServerReader<tessera::v1::UploadMeshRequest>* reader,
                          tessera::v1::Mesh* response) override;
  grpc::Status GetMesh(grpc::ServerContext* context, const tessera::v1::GetMeshRequest* request,
                       tessera::v1::Mesh* response) override;
  grpc::Status ListMeshes(grpc::ServerContext* context,
                          const tessera::v1::ListMeshesRequest* request,
                          tessera::v1::ListMeshesResponse* response) override;
  grpc::Status DeleteMesh(grpc::ServerContext* context,
                          const tessera::v1::DeleteMeshRequest* request,
                          google::protobuf::Empty* response) override;
  grpc::Status DownloadMesh(grpc::ServerContext* context,
                            const tessera::v1::DownloadMeshRequest* request,
                            grpc::ServerWriter<tessera::v1::DownloadMeshResponse>* writer) override;

 private:
  // Feeds every message of the stream to upload, until the client half-closes (or goes away).
  void receive(Watched<grpc::ServerReader<tessera::v1::UploadMeshRequest>>& reader,
               UploadAssembler& upload);
  // The stored mesh a positions-only upload names (header.topology_of); NOT_FOUND naming it.
  std::shared_ptr<const ControlMesh> topologyOf(const std::string& id);

  MeshRepository& repository_;
  AdmissionControl& admission_;
  StreamWatch& streams_;
  const BearerAuth& auth_;
  const UploadLimits limits_;
  ServerMetrics& metrics_;
  PatchSetCache& patches_;
};

}  // namespace tessera::server
