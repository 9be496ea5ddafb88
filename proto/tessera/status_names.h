// Names of gRPC status codes as the gRPC specification spells them ("NOT_FOUND"), for logs,
// metrics labels and CLI error messages on both sides of the API.
#pragma once

#include <grpcpp/support/status.h>

#include <string_view>

namespace tessera {

std::string_view statusCodeName(grpc::StatusCode code);

}  // namespace tessera
