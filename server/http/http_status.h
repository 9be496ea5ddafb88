// A gRPC status as the HTTP response a browser or curl gets from the front door: the HTTP status
// code by the mapping grpc-gateway and Google's REST APIs use (INVALID_ARGUMENT 400,
// UNAUTHENTICATED 401, PERMISSION_DENIED 403, NOT_FOUND 404, ALREADY_EXISTS 409,
// RESOURCE_EXHAUSTED 429, CANCELLED 499, UNIMPLEMENTED 501, UNAVAILABLE 503,
// DEADLINE_EXCEEDED 504, ...), and a JSON body {"code": "NOT_FOUND", "message": "..."} whose
// message is the gRPC one, unchanged.
#pragma once

#include <grpcpp/support/status.h>

#include <string>

namespace tessera::server {

int httpStatusFor(grpc::StatusCode code);
// The JSON body, the code named as gRPC names it (tessera/status_names.h).
std::string errorJson(const grpc::Status& status);

}  // namespace tessera::server
