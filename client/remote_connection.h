// How the `tessera` CLI (and later `tessera bench`) reaches a tessera-server: endpoint options,
// channel creation, per-call metadata, and turning a failed call into a message and exit code.
#pragma once

#include <grpcpp/grpcpp.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace tessera::cli {

inline constexpr const char* kDefaultServer = "127.0.0.1:50051";

struct RemoteEndpoint {
  std::string server = kDefaultServer;  // HOST:PORT, or any gRPC target (dns:///..., ipv4:A,B)
  std::string token;                    // bearer token; empty: none
  bool tls = false;
  std::string caCert;  // PEM file of the CA to trust (implies tls); empty: system roots
};

// Adds --server (TESSERA_SERVER), --token (TESSERA_TOKEN), --tls and --ca-cert to app.
void addEndpointOptions(CLI::App& app, RemoteEndpoint& endpoint);

// The endpoint options as parsed on root (the app addEndpointOptions ran on), for commands
// registered elsewhere, such as the local `tessellate` handing a meshes/ name to the remote one.
RemoteEndpoint endpointFromApp(const CLI::App& root);

// With the API's client service config (proto/tessera/v1/service_config.json: round_robin over
// healthy servers, retries of UNAVAILABLE).
std::shared_ptr<grpc::Channel> makeChannel(const RemoteEndpoint& endpoint);
// The same with channel arguments (e.g. a local subchannel pool, so that the channel gets a
// connection of its own instead of sharing one with every other channel to the same address).
std::shared_ptr<grpc::Channel> makeChannel(const RemoteEndpoint& endpoint,
                                           const grpc::ChannelArguments& arguments);

// Adds the bearer token and, if given, a deadline to context.
void prepareContext(grpc::ClientContext& context, const RemoteEndpoint& endpoint,
                    std::optional<std::chrono::seconds> timeout = std::nullopt);

// Deadline for calls that return quickly (get, list, delete, info).
inline constexpr std::chrono::seconds kUnaryTimeout{30};

// Prints "tessera: <what>: <CODE>: <message>" (and a retry hint if the server gave one) to
// stderr and returns the exit code for status (client/commands.h).
int reportRpcError(std::string_view what, const grpc::Status& status,
                   const grpc::ClientContext* context = nullptr);
int exitCodeFor(grpc::StatusCode code);

// "meshes/x" for "x" or "meshes/x"; the server checks the id itself.
std::string asMeshName(std::string_view nameOrId);

}  // namespace tessera::cli
