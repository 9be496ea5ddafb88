#include "server/calls/status_error.h"

#include <fmt/format.h>

#include <cmath>

namespace tessera::server {

grpc::Status statusFromTesseraError(const TesseraError& error) {
  switch (error.kind()) {
    case ErrorKind::kInvalidInput: return {grpc::StatusCode::INVALID_ARGUMENT, error.what()};
    // The request is well formed but asks for something this server does not implement.
    case ErrorKind::kUnsupported: return {grpc::StatusCode::UNIMPLEMENTED, error.what()};
    case ErrorKind::kLimitExceeded: return {grpc::StatusCode::RESOURCE_EXHAUSTED, error.what()};
  }
  return {grpc::StatusCode::INTERNAL, error.what()};
}

std::string quoteForMessage(std::string_view text) {
  constexpr size_t kMaxQuoted = 80;
  std::string quoted = "\"";
  for (size_t i = 0; i < text.size() && i < kMaxQuoted; ++i) {
    unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += static_cast<char>(c);
    } else if (c >= 0x20 && c < 0x7f) {
      quoted += static_cast<char>(c);
    } else {
      quoted += fmt::format("\\x{:02x}", c);
    }
  }
  if (text.size() > kMaxQuoted) quoted += "...";
  quoted += '"';
  return quoted;
}

}  // namespace tessera::server
