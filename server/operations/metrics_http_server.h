// A minimal HTTP/1.1 responder for Prometheus scrapes: GET /metrics returns the registry's text,
// anything else a 404 or 405. One thread polls every open connection (up to 64), each closed
// after one response; a connection whose request head has not arrived within two seconds of
// accepting it is dropped, so a client that trickles bytes cannot hold up the others. Scrapes
// are rare and tiny, so this is all a metrics port needs, and it avoids another dependency.
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <thread>

namespace tessera::server {

class MetricsHttpServer {
 public:
  // Binds listen ("HOST:PORT", "[::1]:PORT"; port 0 picks a free one). Throws
  // std::runtime_error naming the address when it cannot.
  MetricsHttpServer(const std::string& listen, std::function<std::string()> render);
  ~MetricsHttpServer();
  MetricsHttpServer(const MetricsHttpServer&) = delete;
  MetricsHttpServer& operator=(const MetricsHttpServer&) = delete;

  // The bound address with the actual port.
  std::string address() const { return address_; }
  void start();
  void stop();

 private:
  void serve();
  void respond(int connection, const std::string& head);

  std::function<std::string()> render_;
  int listenFd_ = -1;
  int wakeFds_[2] = {-1, -1};  // a pipe whose write end interrupts poll() on stop
  std::string address_;
  std::thread thread_;
  std::atomic<bool> stopping_{false};
};

// Splits "host:port" or "[v6]:port"; throws std::invalid_argument naming `what` otherwise.
std::pair<std::string, std::string> splitHostPort(const std::string& address, const char* what);

}  // namespace tessera::server
