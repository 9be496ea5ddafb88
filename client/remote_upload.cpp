#include "client/remote_upload.h"

#include <filesystem>
#include <fstream>
#include <vector>

namespace tessera::cli {
namespace {

namespace v1 = tessera::v1;

constexpr size_t kChunkBytes = 64 * 1024;

}  // namespace

grpc::Status uploadObjFile(v1::MeshService::Stub& stub, grpc::ClientContext& context,
                           const std::string& path, const UploadOptions& options, v1::Mesh* mesh,
                           const UploadProgress& progress) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  std::ifstream in(path, std::ios::binary);
  if (error || !in) throw LocalFileError("cannot read " + path);
  const int64_t total = static_cast<int64_t>(size);

  std::unique_ptr<grpc::ClientWriter<v1::UploadMeshRequest>> writer = stub.UploadMesh(&context, mesh);
  v1::UploadMeshRequest request;
  v1::UploadMeshHeader* header = request.mutable_header();
  header->set_mesh_id(options.meshId);
  header->set_display_name(options.displayName.empty()
                               ? std::filesystem::path(path).filename().string()
                               : options.displayName);
  header->set_format(v1::MESH_FORMAT_OBJ);
  *header->mutable_options() = options.subdivision;
  header->set_total_bytes(total);
  // A failed write means the server has already answered (an error); Finish() says which.
  bool open = writer->Write(request);
  std::vector<char> buffer(kChunkBytes);
  int64_t sent = 0;
  while (open && sent < total) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    std::streamsize got = in.gcount();
    if (got <= 0) break;  // the file shrank: the server will report the upload truncated
    request.Clear();
    request.set_obj_data(buffer.data(), static_cast<size_t>(got));
    open = writer->Write(request);
    sent += got;
    if (progress) progress(sent, total);
  }
  writer->WritesDone();
  return writer->Finish();
}

}  // namespace tessera::cli
