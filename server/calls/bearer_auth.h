// Optional bearer-token authentication: when a token is configured, every Tessera call must carry
// "authorization: Bearer <token>". The health service is exempt so that load balancers and
// orchestrators can probe without secrets.
#pragma once

#include <grpcpp/server_context.h>

#include <string>

namespace tessera::server {

class BearerAuth {
 public:
  // An empty token disables authentication.
  explicit BearerAuth(std::string token) : token_(std::move(token)) {}

  bool enabled() const { return !token_.empty(); }
  // Throws StatusError(UNAUTHENTICATED) saying what is wrong with the call's metadata.
  void require(const grpc::ServerContextBase& context) const;

 private:
  std::string token_;
};

}  // namespace tessera::server
