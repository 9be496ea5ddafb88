// tessera-server's settings. Each comes from, in order of precedence, a command-line flag, the
// config file (--config FILE: TOML-style "flag = value" lines, flag names without the dashes,
// unknown names refused), an environment variable (TESSERA_<FLAG>, e.g. TESSERA_LISTEN), or its
// default. (The config file outranks the environment because CLI11 processes them that way.)
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

#include "server/meshes/mesh_upload.h"
#include "server/calls/accuracy_limits.h"

namespace tessera::server {

struct ServerConfig {
  std::string listen = "127.0.0.1:50051";
  std::string store = "sqlite:tessera.db";
  double storeTimeoutSeconds = 10.0;  // a PostgreSQL connection or statement without progress
  std::string token;
  std::string tokenFile;
  std::string tlsCert;
  std::string tlsKey;
  std::string metricsListen = "127.0.0.1:9464";  // "off" disables
  std::string httpListen = "off";                 // the HTTP front door (server/http/), off by default
  std::string httpCorsOrigin;                     // "" sends no CORS headers
  std::string httpWebRoot = TESSERA_DEFAULT_WEB_ROOT;  // the web viewer's files (client/web, built)
  std::string readyFile;
  std::string logLevel = "info";
  std::string logFormat = "text";  // or "json" (log_format.h)
  bool reflection = true;
  int64_t cacheBytes = 512LL << 20;       // decoded meshes
  // Preprocessed patch sets, shared by all engines; negative: a quarter of memoryBudget, so that a
  // larger machine keeps more meshes warm (six large characters' patch sets take ~800 MB).
  int64_t patchCacheBytes = -1;
  std::string engine = "auto";            // "auto", "cpu" or "cuda" (server_app.cpp's makeEngine)
  int64_t deviceCacheBytes = 2LL << 30;   // GPU memory for the CUDA engine's surface trees
  // The whole server's memory (0: 3/4 of the machine's or the container's, machine_memory.h);
  // jobs get what the caches and the server itself (kServerBaseBytes) leave of it.
  int64_t memoryBudget = 0;
  int64_t jobMemoryBytes = 0;  // derived by finalizeServerConfig
  int maxConcurrentJobs = 0;  // 0: the number of hardware threads
  int maxQueuedJobs = -1;     // negative: min(32 x maxConcurrentJobs, maxOpenStreams)
  // The light lane (admission_control.h): its slots (0: maxConcurrentJobs; negative: none) and
  // what makes a tessellation light (job_cost.h).
  int lightJobs = 0;
  int64_t lightJobTriangles = 100'000;
  double drainDelaySeconds = 1.0;  // NOT_SERVING before new calls are refused (shutDown)
  // Then running calls are cancelled, and each job stops within a second (its checkpoints), so
  // the process is gone within drainDelaySeconds + 5 s by default.
  double shutdownGraceSeconds = 4.0;
  int maxOpenStreams = 256;              // streaming calls open at once (server/calls/stream_watch.h)
  double streamIdleSeconds = 30.0;       // a stream's client may take this long to send or read
  double sessionIdleSeconds = 600.0;     // a render session's client, between cameras
  UploadLimits upload;
  TessellationLimits tessellation;
  std::string testEngine;  // hidden: "block" or "pattern", for the server's own tests
};

// What the server holds besides its caches and jobs (code, gRPC, threads), kept out of the jobs'
// share of --memory-budget.
inline constexpr int64_t kServerBaseBytes = 128LL << 20;

// Registers every flag (with its environment variable) and --config on app.
void addServerOptions(CLI::App& app, ServerConfig& config);

// After parsing: reads --token-file, fills derived defaults and checks values; throws
// std::invalid_argument naming the flag.
void finalizeServerConfig(ServerConfig& config);

// Whether a --listen address HOST:PORT accepts connections from this machine only (a loopback
// address or "localhost"); 0.0.0.0, [::] and every other address reach further.
bool listensOnLoopbackOnly(const std::string& listen);

}  // namespace tessera::server
