// One cpp-httplib server bound to a HOST:PORT and served on its own thread: the base of the
// metrics port (server/operations/metrics_http_server.h) and the HTTP front door
// (http_front_door.h). Requests are read with a deadline (a client that trickles bytes is cut off
// after kReadTimeoutSeconds) and served by a small thread pool.
#pragma once

#include <memory>
#include <string>
#include <thread>
#include <utility>

namespace httplib {
class Server;
}

namespace tessera::server {

class HttpListener {
 public:
  static constexpr int kReadTimeoutSeconds = 5;

  // Binds `listen` ("HOST:PORT", "[::1]:PORT"; port 0 picks a free one). Throws
  // std::runtime_error naming `flag` and the address when it cannot, std::invalid_argument when
  // it is not HOST:PORT.
  HttpListener(const std::string& listen, const char* flag);
  ~HttpListener();
  HttpListener(const HttpListener&) = delete;
  HttpListener& operator=(const HttpListener&) = delete;

  // Routes are added here before start().
  httplib::Server& routes() { return *http_; }
  // The bound address with the actual port.
  std::string address() const { return address_; }
  void start();
  void stop();

 private:
  std::unique_ptr<httplib::Server> http_;
  std::string address_;
  std::thread thread_;
};

// Splits "host:port" or "[v6]:port"; throws std::invalid_argument naming `what` otherwise.
std::pair<std::string, std::string> splitHostPort(const std::string& address, const char* what);

}  // namespace tessera::server
