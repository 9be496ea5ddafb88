// Observes every RPC, health and reflection included, from the outside: gives it a request id
// (the client's "x-request-id" if it sent a sane one, echoed back in the initial metadata),
// counts it by method and status, times it, and writes one structured log line when it ends.
// A gRPC server interceptor, so no handler has to remember to do any of this.
#pragma once

#include <grpcpp/server_context.h>
#include <grpcpp/support/server_interceptor.h>

#include "server/operations/log_format.h"
#include "server/operations/server_metrics.h"

namespace tessera::server {

class RequestObserverFactory final
    : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  RequestObserverFactory(ServerMetrics& metrics, LogFormat format) : metrics_(metrics), format_(format) {}
  grpc::experimental::Interceptor* CreateServerInterceptor(
      grpc::experimental::ServerRpcInfo* info) override;

 private:
  ServerMetrics& metrics_;
  const LogFormat format_;
};

}  // namespace tessera::server
