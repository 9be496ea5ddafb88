#include "tests/server/server_process.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "grpc/health/v1/health.grpc.pb.h"

extern char** environ;

namespace tessera::test {
namespace {

// Limits on waiting for the server to start: far above what a healthy start takes (well under a
// second), so that a slow, shared CI machine does not fail the suite.
constexpr auto kStartLimit = std::chrono::seconds(30);
constexpr auto kPollInterval = std::chrono::milliseconds(10);

std::map<std::string, std::string> readKeyValues(const std::filesystem::path& path) {
  std::map<std::string, std::string> values;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    auto eq = line.find('=');
    if (eq != std::string::npos) values[line.substr(0, eq)] = line.substr(eq + 1);
  }
  return values;
}

std::vector<std::string> environmentWith(const std::map<std::string, std::string>& extra) {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) {
    std::string entry = *e;
    // The server must see only the settings a test chooses.
    if (entry.rfind("TESSERA_", 0) == 0) continue;
    env.push_back(entry);
  }
  for (const auto& [key, value] : extra) env.push_back(key + "=" + value);
  return env;
}

pid_t spawn(const std::vector<std::string>& argv, const std::vector<std::string>& env,
            const std::filesystem::path& workDir, const std::filesystem::path& logPath) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, logPath.c_str(),
                                   O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addchdir_np(&actions, workDir.c_str());
  std::vector<char*> args, envp;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  for (const auto& e : env) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);
  pid_t pid = -1;
  int rc = posix_spawn(&pid, argv[0].c_str(), &actions, nullptr, args.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 ? pid : -1;
}

}  // namespace

static_assert(kServing == grpc::health::v1::HealthCheckResponse::SERVING &&
              kNotServing == grpc::health::v1::HealthCheckResponse::NOT_SERVING);

bool waitForHealth(const std::shared_ptr<grpc::Channel>& channel, int wanted, const std::string& service) {
  auto stub = grpc::health::v1::Health::NewStub(channel);
  auto giveUp = std::chrono::steady_clock::now() + kStartLimit;
  while (std::chrono::steady_clock::now() < giveUp) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(2));
    context.set_wait_for_ready(true);
    grpc::health::v1::HealthCheckRequest request;
    request.set_service(service);
    grpc::health::v1::HealthCheckResponse response;
    grpc::Status status = stub->Check(&context, request, &response);
    if (status.ok() && int(response.status()) == wanted) return true;
    std::this_thread::sleep_for(kPollInterval);
  }
  return false;
}

std::unique_ptr<ServerProcess> ServerProcess::start(const std::filesystem::path& workDir,
                                                    const std::vector<std::string>& flags,
                                                    const std::map<std::string, std::string>& env,
                                                    bool awaitServing) {
  std::unique_ptr<ServerProcess> server(new ServerProcess());
  static int serial = 0;
  std::string tag = std::to_string(++serial);
  std::filesystem::path ready = workDir / ("ready-" + tag);
  server->logPath_ = workDir / ("server-" + tag + ".log");
  std::vector<std::string> argv = {TESSERA_SERVER_BINARY, "--metrics-listen", "127.0.0.1:0", "--ready-file",
                                   ready.string()};
  if (std::find(flags.begin(), flags.end(), "--listen") == flags.end()) {
    argv.insert(argv.end(), {"--listen", "127.0.0.1:0"});
  }
  // Stopping fast keeps the suite fast; the tests of draining give their own delay.
  if (std::find(flags.begin(), flags.end(), "--drain-delay") == flags.end()) {
    argv.insert(argv.end(), {"--drain-delay", "0"});
  }
  argv.insert(argv.end(), flags.begin(), flags.end());
  auto tlsCert = std::find(flags.begin(), flags.end(), "--tls-cert");
  if (tlsCert != flags.end() && std::next(tlsCert) != flags.end()) {
    std::ifstream in(*std::next(tlsCert));
    std::stringstream pem;
    pem << in.rdbuf();
    server->tlsCertificate_ = pem.str();
  }
  server->pid_ = spawn(argv, environmentWith(env), workDir, server->logPath_);
  if (server->pid_ <= 0) {
    ADD_FAILURE() << "cannot start " << TESSERA_SERVER_BINARY;
    return nullptr;
  }
  auto giveUp = std::chrono::steady_clock::now() + kStartLimit;
  while (!std::filesystem::exists(ready)) {
    int status = 0;
    bool exited = waitpid(server->pid_, &status, WNOHANG) == server->pid_;
    if (exited || std::chrono::steady_clock::now() > giveUp) {
      if (exited) server->pid_ = -1;
      ADD_FAILURE() << "tessera-server did not start; its log:\n" << server->log();
      return nullptr;
    }
    std::this_thread::sleep_for(kPollInterval);
  }
  auto values = readKeyValues(ready);
  server->address_ = values["grpc"];
  server->metricsAddress_ = values["metrics"];
  server->httpAddress_ = values["http"];
  if (awaitServing && !waitForHealth(server->channel(), kServing)) {
    ADD_FAILURE() << "tessera-server never reported SERVING; its log:\n" << server->log();
    return nullptr;
  }
  return server;
}

ServerProcess::~ServerProcess() {
  if (running()) terminate();
}

std::shared_ptr<grpc::Channel> ServerProcess::channel() const {
  grpc::ChannelArguments args;
  // A channel of its own, so that one test client's connection state never leaks into another's.
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  if (tlsCertificate_.empty()) {
    return grpc::CreateCustomChannel(address_, grpc::InsecureChannelCredentials(), args);
  }
  grpc::SslCredentialsOptions tls;
  tls.pem_root_certs = tlsCertificate_;
  return grpc::CreateCustomChannel(address_, grpc::SslCredentials(tls), args);
}

std::string ServerProcess::log() const {
  std::ifstream in(logPath_);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void ServerProcess::kill9() {
  if (!running()) return;
  ::kill(pid_, SIGKILL);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
}

int ServerProcess::terminate() {
  if (!running()) return -1;
  ::kill(pid_, SIGTERM);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace tessera::test
