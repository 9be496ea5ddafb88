// Streams a mesh to UploadMesh: an OBJ file in 64 KiB chunks (the `upload` command), or arrays
// held in memory (`tessera bench --cold` and tools/soak, which upload copies of stored meshes).
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

#include "tessera/v1/mesh.grpc.pb.h"

namespace tessera::cli {

// A local file could not be read (exit code kExitIo).
class LocalFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct UploadOptions {
  std::string meshId;
  std::string displayName;  // empty: the file name
  tessera::v1::SubdivisionOptions subdivision;
  // "meshes/NAME" for a positions-only upload (UploadMeshHeader.topology_of), else empty.
  std::string topologyOf;
};

// Called with bytes sent so far and the total.
using UploadProgress = std::function<void(int64_t sent, int64_t total)>;

// Uploads the OBJ file at path. Throws LocalFileError if it cannot be read; otherwise returns the
// call's status, with the stored mesh in *mesh on success.
grpc::Status uploadObjFile(tessera::v1::MeshService::Stub& stub, grpc::ClientContext& context,
                           const std::string& path, const UploadOptions& options,
                           tessera::v1::Mesh* mesh, const UploadProgress& progress = {});

// Uploads arrays (MESH_FORMAT_ARRAYS) in messages of a bounded size; the call's status, with the
// stored mesh in *mesh on success.
grpc::Status uploadMeshArrays(tessera::v1::MeshService::Stub& stub, grpc::ClientContext& context,
                              const tessera::v1::MeshArrays& arrays, const UploadOptions& options,
                              tessera::v1::Mesh* mesh);

// What an ARRAYS upload of these arrays declares in total_bytes (mesh.proto's rule).
int64_t arraysUploadBytes(const tessera::v1::MeshArrays& arrays);

}  // namespace tessera::cli
