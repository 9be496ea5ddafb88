// gRPC server reflection v1 (grpc.reflection.v1.ServerReflection), which current clients such as
// grpcurl ask for first; gRPC 1.51's reflection library serves only v1alpha, which the server
// offers beside it. Answers from the generated descriptor pool: the services it is told of, a
// file by name, by a symbol it defines or by an extension, and a type's extension numbers; each
// file response carries the file's dependencies not yet sent on the stream.
#pragma once

#include <string>
#include <vector>

#include "grpc/reflection/v1/reflection.grpc.pb.h"

namespace tessera::server {

class ReflectionV1 final : public grpc::reflection::v1::ServerReflection::Service {
 public:
  explicit ReflectionV1(std::vector<std::string> services) : services_(std::move(services)) {}
  grpc::Status ServerReflectionInfo(
      grpc::ServerContext* context,
      grpc::ServerReaderWriter<grpc::reflection::v1::ServerReflectionResponse,
                               grpc::reflection::v1::ServerReflectionRequest>* stream) override;

 private:
  const std::vector<std::string> services_;  // full names, as list_services reports them
};

}  // namespace tessera::server
