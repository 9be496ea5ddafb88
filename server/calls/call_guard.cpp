#include "server/calls/call_guard.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <new>
#include <string>

#include "core/base/error.h"
#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

bool deadlinePassed(const grpc::ServerContext& context) {
  return std::chrono::system_clock::now() >= context.deadline();
}

grpc::Status cancelledStatus(const grpc::ServerContext& context) {
  if (deadlinePassed(context)) {
    // Starts as gRPC's own client-side message does, so that a client sees the same words
    // whichever side noticed the deadline first.
    return {grpc::StatusCode::DEADLINE_EXCEEDED,
            "Deadline Exceeded: the call's deadline passed before the server finished it"};
  }
  return {grpc::StatusCode::CANCELLED, "the call was cancelled"};
}

}  // namespace

grpc::Status guardCall(grpc::ServerContext& context, const BearerAuth& auth,
                       const std::function<void()>& body) noexcept {
  try {
    auth.require(context);
    body();
    return grpc::Status::OK;
  } catch (const StatusError& error) {
    if (auto retryAfter = error.retryAfterMs()) {
      context.AddTrailingMetadata("grpc-retry-pushback-ms", std::to_string(*retryAfter));
    }
    return error.status();
  } catch (const TesseraError& error) {
    return statusFromTesseraError(error);
  } catch (const OperationCancelled&) {
    return cancelledStatus(context);
  } catch (const std::bad_alloc&) {
    spdlog::error("out of memory in {}", context.peer());
    return {grpc::StatusCode::RESOURCE_EXHAUSTED, "the server ran out of memory for this request"};
  } catch (const std::exception& error) {
    // The exception's text may name internals (libraries, files): the log keeps it.
    spdlog::error("internal error: {}", error.what());
    return {grpc::StatusCode::INTERNAL, "internal error; the server's log has the cause"};
  } catch (...) {
    spdlog::error("internal error: unknown exception");
    return {grpc::StatusCode::INTERNAL, "internal error"};
  }
}

CancellationToken cancellationFor(grpc::ServerContext& context) {
  return CancellationToken(
      [&context] { return context.IsCancelled() || deadlinePassed(context); });
}

}  // namespace tessera::server
