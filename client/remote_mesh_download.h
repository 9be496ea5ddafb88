// Reads a stored mesh back whole with DownloadMesh: its metadata, then its arrays, the chunks
// joined as the server split them. `tessera bench --cold` and tools/soak derive new meshes from it.
#pragma once

#include <grpcpp/grpcpp.h>

#include <string>

#include "tessera/v1/mesh.grpc.pb.h"

namespace tessera::cli {

// name is "meshes/ID". The call's status; on success *mesh and *arrays hold the stored mesh.
grpc::Status downloadMesh(tessera::v1::MeshService::Stub& stub, grpc::ClientContext& context,
                          const std::string& name, tessera::v1::Mesh* mesh,
                          tessera::v1::MeshArrays* arrays);

}  // namespace tessera::cli
