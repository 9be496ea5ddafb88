// The Prometheus scrape port: GET /metrics returns the registry's text exposition, anything else
// a 404. An HttpListener (server/http/http_listener.h) of its own, so that scrapes never queue
// behind the front door's work.
#pragma once

#include <functional>
#include <string>

#include "server/http/http_listener.h"

namespace tessera::server {

class MetricsHttpServer {
 public:
  // Binds listen ("HOST:PORT", "[::1]:PORT"; port 0 picks a free one). Throws
  // std::runtime_error naming the address when it cannot.
  MetricsHttpServer(const std::string& listen, std::function<std::string()> render);

  // The bound address with the actual port.
  std::string address() const { return listener_.address(); }
  void start() { listener_.start(); }
  void stop() { listener_.stop(); }

 private:
  HttpListener listener_;
};

}  // namespace tessera::server
