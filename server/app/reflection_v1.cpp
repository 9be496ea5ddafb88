#include "server/app/reflection_v1.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>

#include <set>

namespace tessera::server {
namespace {

namespace v1 = grpc::reflection::v1;
using google::protobuf::DescriptorPool;
using google::protobuf::FileDescriptor;

// What one stream has sent already: a file's dependencies go out once per stream.
class FileSender {
 public:
  void add(const FileDescriptor* file, v1::FileDescriptorResponse* out) {
    if (!sent_.insert(file->name()).second) return;
    google::protobuf::FileDescriptorProto proto;
    file->CopyTo(&proto);
    out->add_file_descriptor_proto(proto.SerializeAsString());
    for (int d = 0; d < file->dependency_count(); ++d) add(file->dependency(d), out);
  }

 private:
  std::set<std::string> sent_;
};

void notFound(v1::ServerReflectionResponse& response, const std::string& what) {
  response.mutable_error_response()->set_error_code(int(grpc::StatusCode::NOT_FOUND));
  response.mutable_error_response()->set_error_message(what + " not found");
}

void answerFile(const FileDescriptor* file, const std::string& what, FileSender& sender,
                v1::ServerReflectionResponse& response) {
  if (file == nullptr) return notFound(response, what);
  sender.add(file, response.mutable_file_descriptor_response());
}

void answerExtensionNumbers(const std::string& type, v1::ServerReflectionResponse& response) {
  const DescriptorPool* pool = DescriptorPool::generated_pool();
  const auto* message = pool->FindMessageTypeByName(type);
  if (message == nullptr) return notFound(response, "type " + type);
  std::vector<const google::protobuf::FieldDescriptor*> extensions;
  pool->FindAllExtensions(message, &extensions);
  auto* out = response.mutable_all_extension_numbers_response();
  out->set_base_type_name(type);
  for (const auto* extension : extensions) out->add_extension_number(extension->number());
}

}  // namespace

grpc::Status ReflectionV1::ServerReflectionInfo(
    grpc::ServerContext* /*context*/,
    grpc::ServerReaderWriter<v1::ServerReflectionResponse, v1::ServerReflectionRequest>* stream) {
  const DescriptorPool* pool = DescriptorPool::generated_pool();
  FileSender sender;
  v1::ServerReflectionRequest request;
  while (stream->Read(&request)) {
    v1::ServerReflectionResponse response;
    response.set_valid_host(request.host());
    *response.mutable_original_request() = request;
    switch (request.message_request_case()) {
      case v1::ServerReflectionRequest::kFileByFilename:
        answerFile(pool->FindFileByName(request.file_by_filename()),
                   "file " + request.file_by_filename(), sender, response);
        break;
      case v1::ServerReflectionRequest::kFileContainingSymbol:
        answerFile(pool->FindFileContainingSymbol(request.file_containing_symbol()),
                   "symbol " + request.file_containing_symbol(), sender, response);
        break;
      case v1::ServerReflectionRequest::kFileContainingExtension: {
        const auto& asked = request.file_containing_extension();
        const auto* type = pool->FindMessageTypeByName(asked.containing_type());
        const auto* extension =
            type ? pool->FindExtensionByNumber(type, asked.extension_number()) : nullptr;
        answerFile(extension ? extension->file() : nullptr,
                   "extension of " + asked.containing_type(), sender, response);
        break;
      }
      case v1::ServerReflectionRequest::kAllExtensionNumbersOfType:
        answerExtensionNumbers(request.all_extension_numbers_of_type(), response);
        break;
      case v1::ServerReflectionRequest::kListServices:
        for (const std::string& name : services_)
          response.mutable_list_services_response()->add_service()->set_name(name);
        break;
      default:
        response.mutable_error_response()->set_error_code(int(grpc::StatusCode::UNIMPLEMENTED));
        response.mutable_error_response()->set_error_message("the request names no question");
    }
    if (!stream->Write(response)) break;
  }
  return grpc::Status::OK;
}

}  // namespace tessera::server
