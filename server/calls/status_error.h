// The exception a request handler throws when it knows which gRPC status the client should get.
// Handlers are written as straight-line code that throws on the first problem; guardCall()
// (call_guard.h) turns the exception into the status, so no handler forgets a path.
#pragma once

#include <grpcpp/support/status.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/base/error.h"

namespace tessera::server {

class StatusError : public std::runtime_error {
 public:
  StatusError(grpc::StatusCode code, const std::string& message,
              std::optional<int64_t> retryAfterMs = std::nullopt)
      : std::runtime_error(message), code_(code), retryAfterMs_(retryAfterMs) {}

  grpc::StatusCode code() const { return code_; }
  grpc::Status status() const { return grpc::Status(code_, what()); }
  // Set when the client should retry later (server busy): sent as grpc-retry-pushback-ms.
  std::optional<int64_t> retryAfterMs() const { return retryAfterMs_; }

 private:
  grpc::StatusCode code_;
  std::optional<int64_t> retryAfterMs_;
};

[[noreturn]] inline void throwStatus(grpc::StatusCode code, const std::string& message) {
  throw StatusError(code, message);
}
[[noreturn]] inline void throwInvalidArgument(const std::string& message) {
  throw StatusError(grpc::StatusCode::INVALID_ARGUMENT, message);
}
[[noreturn]] inline void throwResourceExhausted(const std::string& message) {
  throw StatusError(grpc::StatusCode::RESOURCE_EXHAUSTED, message);
}

// core/ reports bad input with TesseraError; its kind decides the status and its message, which
// already names the problem and where, is passed on unchanged.
grpc::Status statusFromTesseraError(const TesseraError& error);

// Runs one of core's checks (core/request/accuracy.h, core/request/camera.h, told the field's name): its
// TesseraError becomes the StatusError it maps to, so that every refusal of a request's checks
// is a StatusError, wherever the check runs.
template <typename Check>
void checkWithCore(Check&& check) {
  try {
    check();
  } catch (const TesseraError& error) {
    const grpc::Status status = statusFromTesseraError(error);
    throw StatusError(status.error_code(), status.error_message());
  }
}

// A user-supplied string made safe to quote in a message: printable ASCII only, cut to a length
// that keeps one bad field from flooding logs.
std::string quoteForMessage(std::string_view text);

}  // namespace tessera::server
