#include "server/app/server_info_service.h"

#include "server/calls/call_guard.h"

namespace tessera::server {

grpc::Status ServerInfoServiceImpl::GetServerInfo(grpc::ServerContext* context,
                                                  const tessera::v1::GetServerInfoRequest*,
                                                  tessera::v1::ServerInfo* response) {
  return guardCall(*context, auth_, [&] { *response = info_; });
}

}  // namespace tessera::server
