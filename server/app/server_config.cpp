#include "server/app/server_config.h"

#include <arpa/inet.h>
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "server/calls/admission_control.h"  // formatBytes
#include "server/calls/machine_memory.h"
#include "server/http/http_listener.h"  // splitHostPort

namespace tessera::server {
namespace {

// Every flag reads TESSERA_<NAME> from the environment as well.
CLI::Option* withEnv(CLI::Option* option, const char* env) {
  return option->envname(env);
}

std::string readSecretFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(fmt::format("--token-file: cannot read {}", path));
  std::stringstream text;
  text << in.rdbuf();
  std::string token = text.str();
  while (!token.empty() && (token.back() == '\n' || token.back() == '\r' || token.back() == ' ')) {
    token.pop_back();
  }
  return token;
}

void requirePositive(int64_t value, const char* flag) {
  if (value <= 0) throw std::invalid_argument(fmt::format("{} must be positive", flag));
}

void addLimitOptions(CLI::App& app, ServerConfig& c) {
  const char* group = "Budgets";
  withEnv(app.add_option("--max-upload-bytes", c.upload.maxUploadBytes,
                         "Largest mesh upload (e.g. 256MiB)")
              ->transform(CLI::AsSizeValue(false))
              ->capture_default_str()
              ->group(group),
          "TESSERA_MAX_UPLOAD_BYTES");
  withEnv(app.add_option("--max-vertices", c.upload.mesh.maxVertices, "Most vertices per mesh")
              ->capture_default_str()->group(group),
          "TESSERA_MAX_VERTICES");
  withEnv(app.add_option("--max-faces", c.upload.mesh.maxFaces, "Most faces per mesh")
              ->capture_default_str()->group(group),
          "TESSERA_MAX_FACES");
  withEnv(app.add_option("--max-refined-vertices", c.upload.maxRefinedVertices,
                         "Most vertices OpenSubdiv's refinement of a mesh may make (~650 bytes each)")
              ->capture_default_str()->group(group),
          "TESSERA_MAX_REFINED_VERTICES");
  withEnv(app.add_option("--max-face-size", c.upload.mesh.maxFaceSize, "Most vertices per face")
              ->capture_default_str()->group(group),
          "TESSERA_MAX_FACE_SIZE");
  withEnv(app.add_option("--min-relative-tolerance", c.tessellation.minRelativeTolerance,
                         "Finest tolerance, as a fraction of the bounding-box diagonal")
              ->capture_default_str()->group(group),
          "TESSERA_MIN_RELATIVE_TOLERANCE");
  withEnv(app.add_option("--min-pixel-accuracy", c.tessellation.minPixelAccuracy,
                         "Finest pixel accuracy")
              ->capture_default_str()->group(group),
          "TESSERA_MIN_PIXEL_ACCURACY");
  withEnv(app.add_option("--max-triangles", c.tessellation.maxTriangles,
                         "Most triangles per tessellation")
              ->capture_default_str()->group(group),
          "TESSERA_MAX_TRIANGLES");
  withEnv(app.add_option("--max-uniform-level", c.tessellation.maxUniformLevel,
                         "Highest uniform tessellation level")
              ->capture_default_str()->group(group),
          "TESSERA_MAX_UNIFORM_LEVEL");
  withEnv(app.add_option("--max-image-pixels", c.tessellation.maxImagePixels,
                         "Largest camera viewport (width x height)")
              ->capture_default_str()->group(group),
          "TESSERA_MAX_IMAGE_PIXELS");
  withEnv(app.add_option("--memory-budget", c.memoryBudget,
                         "Memory the whole server may use: caches, jobs (admitted by their estimates) and "
                         "itself (0: 3/4 of the machine's or the container's limit)")
              ->transform(CLI::AsSizeValue(false))
              ->capture_default_str()
              ->group(group),
          "TESSERA_MEMORY_BUDGET");
  withEnv(app.add_option("--max-concurrent-jobs", c.maxConcurrentJobs,
                         "Heavy jobs running at once (0: one per hardware thread)")
              ->capture_default_str()->group(group),
          "TESSERA_MAX_CONCURRENT_JOBS");
  withEnv(app.add_option("--max-queued-jobs", c.maxQueuedJobs,
                         "Heavy jobs waiting; more are refused (negative: 32 per running job, at most --max-open-streams)")
              ->capture_default_str()->group(group),
          "TESSERA_MAX_QUEUED_JOBS");
  withEnv(app.add_option("--light-jobs", c.lightJobs,
                         "Slots of the light lane: jobs known to be short (small uploads, tessellations of a "
                         "preprocessed mesh with a small estimated output) that never queue behind long ones "
                         "(0: as many as --max-concurrent-jobs; negative: no light lane)")
              ->capture_default_str()->group(group),
          "TESSERA_LIGHT_JOBS");
  withEnv(app.add_option("--light-job-triangles", c.lightJobTriangles,
                         "A tessellation of a preprocessed mesh is light when it is estimated to make at most "
                         "this many triangles")
              ->capture_default_str()->group(group),
          "TESSERA_LIGHT_JOB_TRIANGLES");
  withEnv(app.add_option("--max-open-streams", c.maxOpenStreams,
                         "Streaming calls open at once; more are refused")
              ->capture_default_str()->group(group),
          "TESSERA_MAX_OPEN_STREAMS");
  withEnv(app.add_option("--stream-idle-timeout", c.streamIdleSeconds,
                         "Seconds a stream's client may take to send its next message or read ours")
              ->capture_default_str()->group(group),
          "TESSERA_STREAM_IDLE_TIMEOUT");
  withEnv(app.add_option("--session-idle-timeout", c.sessionIdleSeconds,
                         "Seconds a render session may go without a camera update")
              ->capture_default_str()->group(group),
          "TESSERA_SESSION_IDLE_TIMEOUT");
}

}  // namespace

void addServerOptions(CLI::App& app, ServerConfig& c) {
  app.set_config("--config", "", "Read settings from FILE (\"flag = value\" lines)");
  app.allow_config_extras(CLI::config_extras_mode::error);
  withEnv(app.add_option("--listen", c.listen, "gRPC address HOST:PORT (port 0 picks one)")
              ->capture_default_str(),
          "TESSERA_LISTEN");
  withEnv(app.add_option("--store", c.store, "sqlite:PATH or postgresql://USER@HOST:PORT/DB")
              ->capture_default_str(),
          "TESSERA_STORE");
  withEnv(app.add_option("--store-timeout", c.storeTimeoutSeconds,
                         "Seconds a PostgreSQL connection or statement may go without progress")
              ->capture_default_str(),
          "TESSERA_STORE_TIMEOUT");
  withEnv(app.add_option("--token", c.token, "Require \"authorization: Bearer TOKEN\" on calls"),
          "TESSERA_TOKEN");
  withEnv(app.add_option("--token-file", c.tokenFile, "Read the bearer token from FILE"),
          "TESSERA_TOKEN_FILE");
  withEnv(app.add_option("--tls-cert", c.tlsCert, "PEM certificate chain; enables TLS"),
          "TESSERA_TLS_CERT");
  withEnv(app.add_option("--tls-key", c.tlsKey, "PEM private key for --tls-cert"),
          "TESSERA_TLS_KEY");
  withEnv(app.add_option("--metrics-listen", c.metricsListen,
                         "Prometheus /metrics address HOST:PORT, or off")
              ->capture_default_str(),
          "TESSERA_METRICS_LISTEN");
  withEnv(app.add_option("--http-listen", c.httpListen,
                         "HTTP front door (REST/JSON, GLBs, frames) address HOST:PORT, or off")
              ->capture_default_str(),
          "TESSERA_HTTP_LISTEN");
  withEnv(app.add_option("--http-cors-origin", c.httpCorsOrigin,
                         "Origin the HTTP front door allows for browsers (\"*\" for any); none by default"),
          "TESSERA_HTTP_CORS_ORIGIN");
  withEnv(app.add_option("--http-web-root", c.httpWebRoot,
                         "Folder of the web viewer the HTTP front door serves at / (built into build/web)")
              ->capture_default_str(),
          "TESSERA_HTTP_WEB_ROOT");
  withEnv(app.add_option("--ready-file", c.readyFile,
                         "Once serving, write the bound addresses to FILE (for scripts, tests)"),
          "TESSERA_READY_FILE");
  withEnv(app.add_option("--log-level", c.logLevel, "trace, debug, info, warn, error or off")
              ->capture_default_str()
              ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"})),
          "TESSERA_LOG_LEVEL");
  withEnv(app.add_option("--log-format", c.logFormat,
                         "text (time level key=value) or json (one object a line)")
              ->capture_default_str()
              ->check(CLI::IsMember({"text", "json"})),
          "TESSERA_LOG_FORMAT");
  withEnv(app.add_flag("--reflection,!--no-reflection", c.reflection,
                       "Serve gRPC server reflection (off whenever a token is set)"),
          "TESSERA_REFLECTION");
  withEnv(app.add_option("--cache-bytes", c.cacheBytes, "Memory for decoded meshes (e.g. 512MiB)")
              ->transform(CLI::AsSizeValue(false))
              ->capture_default_str(),
          "TESSERA_CACHE_BYTES");
  withEnv(app.add_option("--patch-cache-bytes", c.patchCacheBytes,
                         "Memory for preprocessed patch sets, shared by tessellation and rendering "
                         "(default: a quarter of --memory-budget)")
              ->transform(CLI::AsSizeValue(false)),
          "TESSERA_PATCH_CACHE_BYTES");
  withEnv(app.add_option("--engine", c.engine,
                         "Where tessellation runs: cpu; cuda (the vertices on the GPU, the server "
                         "refuses to start without a CUDA device); auto (cuda when a device is "
                         "present and this build has CUDA, else cpu)")
              ->check(CLI::IsMember({"auto", "cpu", "cuda"}))
              ->capture_default_str(),
          "TESSERA_ENGINE");
  withEnv(app.add_option("--device-cache-bytes", c.deviceCacheBytes,
                         "GPU memory for the CUDA engine's surface trees (one per mesh, least "
                         "recently used dropped first)")
              ->transform(CLI::AsSizeValue(false))
              ->capture_default_str(),
          "TESSERA_DEVICE_CACHE_BYTES");
  withEnv(app.add_option("--drain-delay", c.drainDelaySeconds,
                         "Seconds a stopping server reports NOT_SERVING but still takes calls, so that "
                         "health-checking clients and load balancers move away first")
              ->capture_default_str(),
          "TESSERA_DRAIN_DELAY");
  withEnv(app.add_option("--shutdown-grace", c.shutdownGraceSeconds,
                         "Seconds running calls get to finish on SIGTERM, after the drain delay; then they are "
                         "cancelled and their jobs stop within a second")
              ->capture_default_str(),
          "TESSERA_SHUTDOWN_GRACE");
  addLimitOptions(app, c);
  // Not for operators: engines that make admission and streaming testable (server/tessellation/test_engines.h).
  app.add_option("--test-engine", c.testEngine)->group("")->check(CLI::IsMember({"block", "pattern"}));
}

void finalizeServerConfig(ServerConfig& c) {
  if (!c.tokenFile.empty()) {
    if (!c.token.empty()) throw std::invalid_argument("give --token or --token-file, not both");
    c.token = readSecretFile(c.tokenFile);
    if (c.token.empty()) throw std::invalid_argument("--token-file: the file is empty");
  }
  if (c.tlsCert.empty() != c.tlsKey.empty()) {
    throw std::invalid_argument("--tls-cert and --tls-key go together");
  }
  if (c.maxConcurrentJobs == 0) {
    c.maxConcurrentJobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  }
  // A deep first-come-first-served queue is what keeps clients that ignore the retry hint from
  // taking every freed place from those that wait it out (bench/SOAK-RESULTS.md); a queued job
  // holds a thread and its request, no memory budget. At most the streams the server keeps open.
  if (c.maxQueuedJobs < 0) c.maxQueuedJobs = std::min(32 * c.maxConcurrentJobs, c.maxOpenStreams);
  requirePositive(c.maxConcurrentJobs, "--max-concurrent-jobs");
  requirePositive(c.maxOpenStreams, "--max-open-streams");
  if (c.lightJobs == 0) c.lightJobs = c.maxConcurrentJobs;
  if (c.lightJobTriangles < 0) throw std::invalid_argument("--light-job-triangles must not be negative");
  if (!(c.storeTimeoutSeconds > 0)) throw std::invalid_argument("--store-timeout must be positive");
  if (!(c.drainDelaySeconds >= 0 && c.drainDelaySeconds <= 600)) {
    throw std::invalid_argument("--drain-delay must be between 0 and 600 seconds");
  }
  if (!(c.streamIdleSeconds > 0) || !(c.sessionIdleSeconds > 0)) {
    throw std::invalid_argument("--stream-idle-timeout and --session-idle-timeout must be positive");
  }
  requirePositive(c.upload.maxUploadBytes, "--max-upload-bytes");
  requirePositive(c.upload.mesh.maxVertices, "--max-vertices");
  requirePositive(c.upload.mesh.maxFaces, "--max-faces");
  requirePositive(c.upload.maxRefinedVertices, "--max-refined-vertices");
  requirePositive(c.tessellation.maxTriangles, "--max-triangles");
  requirePositive(c.tessellation.maxUniformLevel, "--max-uniform-level");
  requirePositive(c.tessellation.maxImagePixels, "--max-image-pixels");
  if (c.upload.mesh.maxFaceSize < 3) throw std::invalid_argument("--max-face-size must be >= 3");
  if (!(c.tessellation.minRelativeTolerance > 0 && c.tessellation.minRelativeTolerance < 1)) {
    throw std::invalid_argument("--min-relative-tolerance must be in (0, 1)");
  }
  if (!(c.tessellation.minPixelAccuracy > 0)) {
    throw std::invalid_argument("--min-pixel-accuracy must be positive");
  }
  if (c.cacheBytes < 0) throw std::invalid_argument("--cache-bytes must not be negative");
  if (c.deviceCacheBytes < 0) throw std::invalid_argument("--device-cache-bytes must not be negative");
  if (c.memoryBudget < 0) throw std::invalid_argument("--memory-budget must not be negative");
  if (c.memoryBudget == 0) c.memoryBudget = machineMemoryBytes() / 4 * 3;
  if (c.patchCacheBytes < 0) c.patchCacheBytes = c.memoryBudget / 4;
  c.jobMemoryBytes = c.memoryBudget - c.cacheBytes - c.patchCacheBytes - kServerBaseBytes;
  if (c.jobMemoryBytes < kServerBaseBytes) {
    throw std::invalid_argument(fmt::format(
        "--memory-budget {} leaves {} for jobs after --cache-bytes {}, --patch-cache-bytes {} and {} for the "
        "server itself; raise it to at least {} or lower the caches",
        formatBytes(c.memoryBudget), formatBytes(std::max<int64_t>(c.jobMemoryBytes, 0)), formatBytes(c.cacheBytes),
        formatBytes(c.patchCacheBytes), formatBytes(kServerBaseBytes),
        formatBytes(c.cacheBytes + c.patchCacheBytes + 2 * kServerBaseBytes)));
  }
}

bool listensOnLoopbackOnly(const std::string& listen) {
  const std::string host = splitHostPort(listen, "--listen").first;
  if (host == "localhost") return true;
  in_addr v4{};
  if (inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  return inet_pton(AF_INET6, host.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

}  // namespace tessera::server
