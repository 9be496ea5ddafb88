// The one place where a handler's exceptions become gRPC statuses. Every Tessera RPC body runs
// inside guardCall(), which first checks authentication, so no handler can forget either.
#pragma once

#include <grpcpp/server_context.h>

#include <functional>

#include "server/calls/bearer_auth.h"
#include "server/calls/cancellation.h"

namespace tessera::server {

// Runs body; returns OK if it returns normally, otherwise the status its exception maps to:
// StatusError as given (adding grpc-retry-pushback-ms for retryable refusals), TesseraError by
// kind, OperationCancelled as CANCELLED or DEADLINE_EXCEEDED, anything else as INTERNAL (logged).
grpc::Status guardCall(grpc::ServerContext& context, const BearerAuth& auth,
                       const std::function<void()>& body) noexcept;

// A token that fires when the client cancels, hangs up or its deadline passes.
CancellationToken cancellationFor(grpc::ServerContext& context);

}  // namespace tessera::server
