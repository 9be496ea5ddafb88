// tessera.v1.ServerInfoService: version, backends, device and limits, so that clients can check
// budgets before sending work.
#pragma once

#include "server/calls/bearer_auth.h"
#include "tessera/v1/server_info.grpc.pb.h"

namespace tessera::server {

class ServerInfoServiceImpl final : public tessera::v1::ServerInfoService::Service {
 public:
  // info is fixed for the server's lifetime.
  ServerInfoServiceImpl(tessera::v1::ServerInfo info, const BearerAuth& auth)
      : info_(std::move(info)), auth_(auth) {}

  grpc::Status GetServerInfo(grpc::ServerContext* context,
                             const tessera::v1::GetServerInfoRequest* request,
                             tessera::v1::ServerInfo* response) override;

 private:
  const tessera::v1::ServerInfo info_;
  const BearerAuth& auth_;
};

}  // namespace tessera::server
