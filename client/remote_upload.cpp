#include "client/remote_upload.h"

#include <filesystem>
#include <fstream>
#include <vector>

namespace tessera::cli {
namespace {

namespace v1 = tessera::v1;

constexpr size_t kChunkBytes = 64 * 1024;
// Array elements per message: 64K floats are 256 KiB, far under gRPC's 4 MiB message limit.
constexpr int kElementsPerMessage = 64 * 1024;

// Appends field's elements to the last message, starting a new one when it is full (a field
// may continue in the next message: the server concatenates them).
template <typename Field, typename Add>
void spread(const Field& field, std::vector<v1::MeshArrays>& messages, int& used, Add add) {
  for (const auto& value : field) {
    if (used == kElementsPerMessage) messages.emplace_back(), used = 0;
    add(messages.back(), value);
    ++used;
  }
}

std::vector<v1::MeshArrays> splitArrays(const v1::MeshArrays& a) {
  std::vector<v1::MeshArrays> messages(1);
  int used = 0;
  spread(a.positions(), messages, used, [](v1::MeshArrays& m, float v) { m.add_positions(v); });
  spread(a.face_sizes(), messages, used, [](v1::MeshArrays& m, int32_t v) { m.add_face_sizes(v); });
  spread(a.face_vertices(), messages, used,
         [](v1::MeshArrays& m, int32_t v) { m.add_face_vertices(v); });
  spread(a.creases(), messages, used,
         [](v1::MeshArrays& m, const v1::Crease& v) { *m.add_creases() = v; });
  spread(a.corners(), messages, used,
         [](v1::MeshArrays& m, const v1::Corner& v) { *m.add_corners() = v; });
  spread(a.holes(), messages, used, [](v1::MeshArrays& m, int32_t v) { m.add_holes(v); });
  spread(a.uvs(), messages, used, [](v1::MeshArrays& m, float v) { m.add_uvs(v); });
  spread(a.uv_indices(), messages, used, [](v1::MeshArrays& m, int32_t v) { m.add_uv_indices(v); });
  if (a.has_origin()) *messages.front().mutable_origin() = a.origin();
  return messages;
}

v1::UploadMeshRequest headerFor(const UploadOptions& options, v1::MeshFormat format, int64_t total,
                                const std::string& defaultName) {
  v1::UploadMeshRequest request;
  v1::UploadMeshHeader* header = request.mutable_header();
  header->set_mesh_id(options.meshId);
  header->set_display_name(options.displayName.empty() ? defaultName : options.displayName);
  header->set_format(format);
  *header->mutable_options() = options.subdivision;
  header->set_total_bytes(total);
  header->set_topology_of(options.topologyOf);
  return request;
}

}  // namespace

int64_t arraysUploadBytes(const v1::MeshArrays& a) {
  const int64_t numbers = a.positions_size() + a.face_sizes_size() + a.face_vertices_size() +
                          a.holes_size() + a.uvs_size() + a.uv_indices_size();
  return 4 * numbers + 12 * int64_t(a.creases_size()) + 8 * int64_t(a.corners_size()) +
         (a.has_origin() ? 24 : 0);
}

grpc::Status uploadMeshArrays(v1::MeshService::Stub& stub, grpc::ClientContext& context,
                              const v1::MeshArrays& arrays, const UploadOptions& options,
                              v1::Mesh* mesh) {
  std::unique_ptr<grpc::ClientWriter<v1::UploadMeshRequest>> writer =
      stub.UploadMesh(&context, mesh);
  // A failed write means the server has already answered (an error); Finish() says which.
  bool open = writer->Write(
      headerFor(options, v1::MESH_FORMAT_ARRAYS, arraysUploadBytes(arrays), options.meshId));
  for (v1::MeshArrays& piece : splitArrays(arrays)) {
    if (!open) break;
    v1::UploadMeshRequest request;
    *request.mutable_arrays() = std::move(piece);
    open = writer->Write(request);
  }
  writer->WritesDone();
  return writer->Finish();
}

grpc::Status uploadObjFile(v1::MeshService::Stub& stub, grpc::ClientContext& context,
                           const std::string& path, const UploadOptions& options, v1::Mesh* mesh,
                           const UploadProgress& progress) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  std::ifstream in(path, std::ios::binary);
  if (error || !in) throw LocalFileError("cannot read " + path);
  const int64_t total = static_cast<int64_t>(size);

  std::unique_ptr<grpc::ClientWriter<v1::UploadMeshRequest>> writer = stub.UploadMesh(&context, mesh);
  v1::UploadMeshRequest request = headerFor(options, v1::MESH_FORMAT_OBJ, total,
                                            std::filesystem::path(path).filename().string());
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
