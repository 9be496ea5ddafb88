#include "server/calls/bearer_auth.h"

#include <string_view>

#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

// Compares in time independent of where the strings first differ, so that response timing does
// not reveal a prefix of the token.
bool constantTimeEqual(std::string_view a, std::string_view b) {
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  for (size_t i = 0; i < a.size(); ++i) {
    diff |= static_cast<unsigned char>(a[i] ^ (b.empty() ? 0 : b[i % b.size()]));
  }
  return diff == 0;
}

[[noreturn]] void unauthenticated(const std::string& why) {
  throwStatus(grpc::StatusCode::UNAUTHENTICATED, why);
}

}  // namespace

void BearerAuth::require(const grpc::ServerContextBase& context) const {
  if (!enabled()) return;
  const auto& metadata = context.client_metadata();
  auto [first, last] = metadata.equal_range("authorization");
  if (first == last) {
    unauthenticated(
        "missing authorization metadata: this server requires \"authorization: Bearer <token>\"");
  }
  if (std::next(first) != last) unauthenticated("authorization metadata was sent more than once");
  std::string_view value(first->second.data(), first->second.size());
  constexpr std::string_view kScheme = "Bearer ";
  if (value.size() <= kScheme.size() || value.substr(0, kScheme.size()) != kScheme) {
    unauthenticated("authorization metadata is not of the form \"Bearer <token>\"");
  }
  if (!constantTimeEqual(value.substr(kScheme.size()), token_)) {
    unauthenticated("invalid bearer token");
  }
}

}  // namespace tessera::server
