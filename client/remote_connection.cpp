#include "client/remote_connection.h"

#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <sstream>

#include "client/commands.h"
#include "tessera/service_config.h"
#include "tessera/status_names.h"

namespace tessera::cli {
namespace {

std::string readPem(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("--ca-cert: cannot read " + path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Values of an option as parsed (command line or environment), or fallback.
std::string optionValue(const CLI::App& root, const char* name, const std::string& fallback) {
  const CLI::Option* option = root.get_option_no_throw(name);
  if (!option || option->results().empty()) return fallback;
  return option->results().back();
}

}  // namespace

void addEndpointOptions(CLI::App& app, RemoteEndpoint& endpoint) {
  const char* group = "Server connection";
  app.add_option("--server", endpoint.server,
                 "tessera-server address HOST:PORT, or a gRPC target with several (dns:///NAME:PORT, ipv4:A:P,B:P)")
      ->envname("TESSERA_SERVER")
      ->capture_default_str()
      ->group(group);
  app.add_option("--token", endpoint.token, "Bearer token the server requires")
      ->envname("TESSERA_TOKEN")
      ->group(group);
  app.add_flag("--tls", endpoint.tls, "Connect with TLS (system root certificates)")->group(group);
  app.add_option("--ca-cert", endpoint.caCert, "Trust this PEM CA certificate (implies --tls)")
      ->group(group);
}

RemoteEndpoint endpointFromApp(const CLI::App& root) {
  RemoteEndpoint endpoint;
  endpoint.server = optionValue(root, "--server", kDefaultServer);
  endpoint.token = optionValue(root, "--token", "");
  endpoint.caCert = optionValue(root, "--ca-cert", "");
  const CLI::Option* tls = root.get_option_no_throw("--tls");
  endpoint.tls = tls && tls->count() > 0;
  return endpoint;
}

std::shared_ptr<grpc::Channel> makeChannel(const RemoteEndpoint& endpoint) {
  return makeChannel(endpoint, grpc::ChannelArguments());
}

std::shared_ptr<grpc::Channel> makeChannel(const RemoteEndpoint& endpoint,
                                           const grpc::ChannelArguments& arguments) {
  std::shared_ptr<grpc::ChannelCredentials> credentials;
  if (endpoint.tls || !endpoint.caCert.empty()) {
    grpc::SslCredentialsOptions options;
    if (!endpoint.caCert.empty()) options.pem_root_certs = readPem(endpoint.caCert);
    credentials = grpc::SslCredentials(options);
  } else {
    credentials = grpc::InsecureChannelCredentials();
  }
  grpc::ChannelArguments withPolicy = arguments;
  withPolicy.SetServiceConfigJSON(tessera::kClientServiceConfig);
  return grpc::CreateCustomChannel(endpoint.server, credentials, withPolicy);
}

void prepareContext(grpc::ClientContext& context, const RemoteEndpoint& endpoint,
                    std::optional<std::chrono::seconds> timeout) {
  // Sent as plain metadata rather than call credentials, which gRPC withholds on insecure
  // channels: a loopback or private-network deployment may still use a token.
  if (!endpoint.token.empty()) context.AddMetadata("authorization", "Bearer " + endpoint.token);
  if (timeout) context.set_deadline(std::chrono::system_clock::now() + *timeout);
}

int exitCodeFor(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return kExitOk;
    case grpc::StatusCode::INVALID_ARGUMENT: return kExitInvalidInput;
    case grpc::StatusCode::UNIMPLEMENTED: return kExitUnsupported;
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return kExitLimit;
    default: return kExitRemote;
  }
}

int reportRpcError(std::string_view what, const grpc::Status& status,
                   const grpc::ClientContext* context) {
  std::cerr << fmt::format("tessera: {}: {}: {}\n", what, statusCodeName(status.error_code()),
                           status.error_message());
  if (context) {
    const auto& trailers = context->GetServerTrailingMetadata();
    auto retry = trailers.find("grpc-retry-pushback-ms");
    if (retry != trailers.end()) {
      std::cerr << fmt::format("tessera: the server asks to retry after {} ms\n",
                               std::string_view(retry->second.data(), retry->second.size()));
    }
  }
  return exitCodeFor(status.error_code());
}

std::string asMeshName(std::string_view nameOrId) {
  constexpr std::string_view kPrefix = "meshes/";
  if (nameOrId.substr(0, kPrefix.size()) == kPrefix) return std::string(nameOrId);
  return std::string(kPrefix) + std::string(nameOrId);
}

}  // namespace tessera::cli
