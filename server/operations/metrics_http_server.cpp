#include "server/operations/metrics_http_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace tessera::server {
namespace {

constexpr int kIoTimeoutMs = 2000;
constexpr size_t kMaxRequestBytes = 8192;
constexpr size_t kMaxConnections = 64;  // open at once; more are closed on arrival

void closeFd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

int bindListener(const std::string& host, const std::string& port, std::string& bound) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  if (int rc = getaddrinfo(host.c_str(), port.c_str(), &hints, &found); rc != 0) {
    throw std::runtime_error(fmt::format("metrics address {}:{}: {}", host, port, gai_strerror(rc)));
  }
  int fd = ::socket(found->ai_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  int one = 1;
  if (fd >= 0) ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (fd < 0 || ::bind(fd, found->ai_addr, found->ai_addrlen) != 0 || ::listen(fd, 16) != 0) {
    std::string why = std::strerror(errno);
    freeaddrinfo(found);
    if (fd >= 0) ::close(fd);
    throw std::runtime_error(fmt::format("cannot listen for metrics on {}:{}: {}", host, port, why));
  }
  freeaddrinfo(found);
  sockaddr_storage addr{};
  socklen_t length = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &length);
  int actualPort = ntohs(addr.ss_family == AF_INET6
                             ? reinterpret_cast<sockaddr_in6*>(&addr)->sin6_port
                             : reinterpret_cast<sockaddr_in*>(&addr)->sin_port);
  bound = host.find(':') != std::string::npos ? fmt::format("[{}]:{}", host, actualPort)
                                              : fmt::format("{}:{}", host, actualPort);
  return fd;
}

bool headComplete(const std::string& head) {
  return head.find("\r\n\r\n") != std::string::npos || head.find("\n\n") != std::string::npos;
}

// Sends the whole response within kIoTimeoutMs in all; a client that does not read loses it.
void sendAll(int fd, std::string_view data) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(kIoTimeoutMs);
  while (!data.empty()) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd p{fd, POLLOUT, 0};
    if (left.count() <= 0 || ::poll(&p, 1, int(left.count())) <= 0) return;
    ssize_t n = ::send(fd, data.data(), data.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (n <= 0) return;
    data.remove_prefix(static_cast<size_t>(n));
  }
}

std::string response(int status, const char* reason, const std::string& contentType,
                     const std::string& body) {
  return fmt::format(
      "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{}",
      status, reason, contentType, body.size(), body);
}

}  // namespace

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

MetricsHttpServer::MetricsHttpServer(const std::string& listen,
                                     std::function<std::string()> render)
    : render_(std::move(render)) {
  auto [host, port] = splitHostPort(listen, "--metrics-listen");
  listenFd_ = bindListener(host, port, address_);
  if (::pipe2(wakeFds_, O_CLOEXEC) != 0) {
    closeFd(listenFd_);
    throw std::runtime_error("cannot create a pipe for the metrics server");
  }
}

MetricsHttpServer::~MetricsHttpServer() {
  stop();
  closeFd(listenFd_);
  closeFd(wakeFds_[0]);
  closeFd(wakeFds_[1]);
}

void MetricsHttpServer::start() { thread_ = std::thread([this] { serve(); }); }

void MetricsHttpServer::stop() {
  if (stopping_.exchange(true)) return;
  char byte = 0;
  [[maybe_unused]] ssize_t ignored = ::write(wakeFds_[1], &byte, 1);
  if (thread_.joinable()) thread_.join();
}

// One thread serves every connection: each is read as its bytes arrive (poll over all of them)
// and must deliver its request head within kIoTimeoutMs of being accepted, so a client that
// trickles bytes holds only its own connection, never the scrapes beside it.
void MetricsHttpServer::serve() {
  struct Pending {
    int fd;
    std::string head;
    std::chrono::steady_clock::time_point deadline;
  };
  std::vector<Pending> pending;
  std::vector<pollfd> fds;
  while (!stopping_) {
    const auto now = std::chrono::steady_clock::now();
    int timeout = -1;
    for (const Pending& p : pending) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(p.deadline - now).count();
      timeout = timeout < 0 ? int(std::max<int64_t>(left, 0)) : std::min(timeout, int(std::max<int64_t>(left, 0)));
    }
    fds.assign({{listenFd_, POLLIN, 0}, {wakeFds_[0], POLLIN, 0}});
    for (const Pending& p : pending) fds.push_back({p.fd, POLLIN, 0});
    if (::poll(fds.data(), fds.size(), timeout) < 0) {
      if (errno == EINTR) continue;
      spdlog::error("metrics server: poll failed: {}", std::strerror(errno));
      break;
    }
    if (fds[1].revents) break;
    // Requests that arrived (or ended, or ran out of time), then new connections.
    const auto after = std::chrono::steady_clock::now();
    std::vector<Pending> kept;
    for (size_t i = 0; i < pending.size(); ++i) {
      Pending& p = pending[i];
      bool done = false;
      if (fds[i + 2].revents) {
        char buffer[1024];
        const ssize_t n = ::recv(p.fd, buffer, sizeof buffer, MSG_DONTWAIT);
        if (n > 0) p.head.append(buffer, size_t(n));
        done = n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR) || p.head.size() > kMaxRequestBytes;
        if (!done && headComplete(p.head)) {
          respond(p.fd, p.head);
          done = true;
        }
      }
      if (!done && after >= p.deadline) done = true;
      if (done) {
        ::close(p.fd);
      } else {
        kept.push_back(std::move(p));
      }
    }
    pending.swap(kept);
    if (fds[0].revents) {
      const int connection = ::accept4(listenFd_, nullptr, nullptr, SOCK_CLOEXEC);
      if (connection >= 0 && pending.size() >= kMaxConnections) {
        ::close(connection);
      } else if (connection >= 0) {
        pending.push_back({connection, {}, after + std::chrono::milliseconds(kIoTimeoutMs)});
      }
    }
  }
  for (Pending& p : pending) ::close(p.fd);
}

void MetricsHttpServer::respond(int connection, const std::string& head) {
  std::string_view line(head.data(), head.find_first_of("\r\n"));
  bool isGet = line.substr(0, 4) == "GET ";
  bool isHead = line.substr(0, 5) == "HEAD ";
  size_t pathStart = line.find(' ') + 1;
  std::string_view path = line.substr(pathStart, line.find(' ', pathStart) - pathStart);
  path = path.substr(0, path.find('?'));
  if (!isGet && !isHead) {
    sendAll(connection, response(405, "Method Not Allowed", "text/plain", "only GET\n"));
  } else if (path != "/metrics") {
    sendAll(connection, response(404, "Not Found", "text/plain", "try /metrics\n"));
  } else {
    std::string body = render_();
    std::string full = response(200, "OK", "text/plain; version=0.0.4; charset=utf-8", body);
    sendAll(connection, isHead ? std::string_view(full).substr(0, full.size() - body.size())
                               : std::string_view(full));
  }
}

}  // namespace tessera::server
