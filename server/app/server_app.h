// Assembles and runs tessera-server: store, cache, admission control, engine, gRPC services with
// health and reflection, the metrics endpoint; then serves until SIGINT or SIGTERM and shuts
// down gracefully (health NOT_SERVING first, then running calls get a grace period).
#pragma once

#include "server/app/server_config.h"

namespace tessera::server {

// Returns the process exit code; logs why when it cannot start.
int runServer(const ServerConfig& config);

}  // namespace tessera::server
