#include "server/operations/metrics_http_server.h"

#include <httplib.h>

#include <utility>

namespace tessera::server {

MetricsHttpServer::MetricsHttpServer(const std::string& listen, std::function<std::string()> render)
    : listener_(listen, "--metrics-listen") {
  listener_.routes().Get("/metrics", [render = std::move(render)](const httplib::Request&, httplib::Response& response) {
    response.set_content(render(), "text/plain; version=0.0.4; charset=utf-8");
  });
}

}  // namespace tessera::server
