// Streams a mesh file to UploadMesh in 64 KiB chunks. Shared by the `upload` command and, later,
// `tessera bench`, which uploads the same way.
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
};

// Called with bytes sent so far and the total.
using UploadProgress = std::function<void(int64_t sent, int64_t total)>;

// Uploads the OBJ file at path. Throws LocalFileError if it cannot be read; otherwise returns the
// call's status, with the stored mesh in *mesh on success.
grpc::Status uploadObjFile(tessera::v1::MeshService::Stub& stub, grpc::ClientContext& context,
                           const std::string& path, const UploadOptions& options,
                           tessera::v1::Mesh* mesh, const UploadProgress& progress = {});

}  // namespace tessera::cli
