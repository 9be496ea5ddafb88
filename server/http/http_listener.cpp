#include "server/http/http_listener.h"

#include <fmt/format.h>
#include <httplib.h>
#include <sys/socket.h>

#include <stdexcept>

namespace tessera::server {

std::pair<std::string, std::string> splitHostPort(const std::string& address, const char* what) {
  size_t colon = address.rfind(':');
  if (colon == std::string::npos || colon + 1 == address.size()) {
    throw std::invalid_argument(fmt::format("{} \"{}\" is not HOST:PORT", what, address));
  }
  std::string host = address.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  return {host, address.substr(colon + 1)};
}

HttpListener::HttpListener(const std::string& listen, const char* flag) : http_(std::make_unique<httplib::Server>()) {
  auto [host, portText] = splitHostPort(listen, flag);
  int port = -1;
  try {
    size_t used = 0;
    port = std::stoi(portText, &used);
    if (used != portText.size()) port = -1;
  } catch (const std::exception&) {
  }
  if (port < 0 || port > 65535) throw std::invalid_argument(fmt::format("{} \"{}\": bad port", flag, listen));
  http_->set_address_family(AF_UNSPEC);
  http_->set_read_timeout(kReadTimeoutSeconds, 0);
  const int bound = port == 0 ? http_->bind_to_any_port(host) : (http_->bind_to_port(host, port) ? port : -1);
  if (bound <= 0) throw std::runtime_error(fmt::format("{}: cannot listen on {}", flag, listen));
  address_ = host.find(':') != std::string::npos ? fmt::format("[{}]:{}", host, bound) : fmt::format("{}:{}", host, bound);
}

HttpListener::~HttpListener() { stop(); }

void HttpListener::start() {
  thread_ = std::thread([this] { http_->listen_after_bind(); });
}

void HttpListener::stop() {
  http_->stop();
  if (thread_.joinable()) thread_.join();
}

}  // namespace tessera::server
