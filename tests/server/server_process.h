// Runs the real tessera-server binary for a test: on a free loopback port (the server binds port
// 0 and reports the port in its ready file), with its log in the test's temporary folder, and
// stops it (or SIGKILLs it) on request or at the end of the test.
#pragma once

#include <grpcpp/grpcpp.h>
#include <sys/types.h>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace tessera::test {

class ServerProcess {
 public:
  // Starts the server with the given flags (plus --metrics-listen, --ready-file and, unless the
  // flags give them, --listen chosen here and --drain-delay 0) in workDir and waits until it has written its ready file and, unless
  // awaitServing is false, until its health service says SERVING. Fails the current test
  // (fatally) if it does not start, printing the server's log.
  static std::unique_ptr<ServerProcess> start(const std::filesystem::path& workDir,
                                              const std::vector<std::string>& flags,
                                              const std::map<std::string, std::string>& env = {},
                                              bool awaitServing = true);
  ~ServerProcess();
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  const std::string& address() const { return address_; }
  const std::string& metricsAddress() const { return metricsAddress_; }
  // The HTTP front door's address when the flags asked for one (--http-listen), else "".
  const std::string& httpAddress() const { return httpAddress_; }
  // A new channel (connections are not shared between channels made here); with TLS when the
  // server was started with --tls-cert, trusting that certificate.
  std::shared_ptr<grpc::Channel> channel() const;
  std::string log() const;

  // SIGKILL, then reap: the process gets no chance to clean up.
  void kill9();
  // SIGTERM, then reap; returns the exit status (or -1 if it died of a signal).
  int terminate();
  bool running() const { return pid_ > 0; }
  // The server's process id (for /proc/PID/status), or -1 once it has stopped.
  pid_t pid() const { return pid_; }

 private:
  ServerProcess() = default;
  pid_t pid_ = -1;
  std::filesystem::path logPath_;
  std::string address_;
  std::string metricsAddress_;
  std::string httpAddress_;
  std::string tlsCertificate_;  // PEM, when the server runs with TLS
};

// Waits (with a generous limit) until the server at channel reports `wanted` (the numbers of
// grpc.health.v1's ServingStatus: 1 SERVING, 2 NOT_SERVING) for `service` ("": the server);
// false if it never does.
inline constexpr int kServing = 1, kNotServing = 2;
bool waitForHealth(const std::shared_ptr<grpc::Channel>& channel, int wanted, const std::string& service = "");

}  // namespace tessera::test
