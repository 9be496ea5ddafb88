// tessera-server: the Tessera gRPC service (see server/app/server_app.h and proto/tessera/v1/).
#include <spdlog/spdlog.h>

#include <iostream>

#include "server/calls/memory_release.h"
#include "server/operations/log_format.h"
#include "server/store/mesh_store.h"
#include "server/app/server_app.h"
#include "server/app/server_config.h"

int main(int argc, char** argv) {
  tessera::server::mapLargeBlocks();
  CLI::App app{"tessera-server: remote tessellation of Catmull-Clark subdivision surfaces"};
  tessera::server::ServerConfig config;
  tessera::server::addServerOptions(app, config);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    tessera::server::finalizeServerConfig(config);
  } catch (const std::invalid_argument& e) {
    std::cerr << "tessera-server: " << e.what() << "\n";
    return 2;
  }
  spdlog::set_level(spdlog::level::from_str(config.logLevel));
  tessera::server::useLogFormat(tessera::server::logFormatNamed(config.logFormat));
  try {
    return tessera::server::runServer(config);
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 1;
  }
}
