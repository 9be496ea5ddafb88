#include "client/remote_mesh_download.h"

namespace tessera::cli {

grpc::Status downloadMesh(tessera::v1::MeshService::Stub& stub, grpc::ClientContext& context,
                          const std::string& name, tessera::v1::Mesh* mesh,
                          tessera::v1::MeshArrays* arrays) {
  tessera::v1::DownloadMeshRequest request;
  request.set_name(name);
  auto reader = stub.DownloadMesh(&context, request);
  tessera::v1::DownloadMeshResponse message;
  while (reader->Read(&message)) {
    if (message.has_mesh()) *mesh = message.mesh();
    // Protobuf's merge appends repeated fields, which is how mesh.proto joins chunks.
    if (message.has_arrays()) arrays->MergeFrom(message.arrays());
  }
  return reader->Finish();
}

}  // namespace tessera::cli
