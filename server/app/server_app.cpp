#include "server/app/server_app.h"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/impl/server_builder_option.h>
#include <grpcpp/resource_quota.h>
#include <fmt/format.h>
#include <signal.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>

#include "core/base/version.h"

#include "server/app/reflection_v1.h"
#include "server/app/server_info_service.h"
#include "server/app/tls_key_pair.h"
#include "server/calls/stream_watch.h"
#include "server/http/http_front_door.h"
#include "server/meshes/mesh_service.h"
#include "server/meshes/patch_set_cache.h"
#include "server/operations/log_format.h"
#include "server/operations/metrics_http_server.h"
#include "server/operations/process_metrics.h"
#include "server/operations/request_observer.h"
#include "server/render/render_backend_factory.h"
#include "server/render/render_service.h"
#include "server/store/store_health.h"
#include "server/tessellation/engine_choice.h"
#include "server/tessellation/tessellation_service.h"
#include "server/tessellation/test_engines.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

// Enough threads for every admitted and queued job plus cheap calls; past it gRPC itself
// refuses new calls with RESOURCE_EXHAUSTED instead of the process spawning threads without end.
constexpr int kMaxServerThreads = 512;

std::string readFile(const std::string& path, const char* flag) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(std::string(flag) + ": cannot read " + path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::shared_ptr<grpc::ServerCredentials> serverCredentials(const ServerConfig& config) {
  if (config.tlsCert.empty()) return grpc::InsecureServerCredentials();
  grpc::SslServerCredentialsOptions options;
  const std::string key = readFile(config.tlsKey, "--tls-key"), certificate = readFile(config.tlsCert, "--tls-cert");
  checkTlsKeyPair(certificate, key);
  options.pem_key_cert_pairs.push_back({key, certificate});
  return grpc::SslServerCredentials(options);
}

std::unique_ptr<TessellationEngine> makeEngine(const ServerConfig& config, PatchSetCache& patches) {
  if (config.testEngine.empty()) return chooseEngine(config.engine, size_t(config.deviceCacheBytes), patches);
  spdlog::warn("using the test engine \"{}\": results are not geometry", config.testEngine);
  return makeTestEngine(config.testEngine);
}

v1::ServerInfo describeServer(const ServerConfig& config, const TessellationEngine& engine,
                              const RenderBackend& renderer, const std::string& storeKind) {
  v1::ServerInfo info;
  info.set_version(kVersion);
  v1::Backend* backend = info.add_backends();
  backend->set_name(engine.name());
  backend->set_available(engine.available());
  backend->set_detail(engine.detail());
  v1::Backend* render = info.add_backends();
  render->set_name(renderer.name());
  render->set_available(renderer.available());
  render->set_detail(renderer.detail());
  std::string device = fmt::format("CPU: {} hardware threads", std::thread::hardware_concurrency());
  if (!engine.device().empty()) device += "; tessellation device: " + engine.device();
  if (!renderer.device().empty()) device += "; render device: " + renderer.device();
  info.set_device(device);
  v1::ServerLimits* limits = info.mutable_limits();
  limits->set_max_upload_bytes(config.upload.maxUploadBytes);
  limits->set_max_vertices(config.upload.mesh.maxVertices);
  limits->set_max_faces(config.upload.mesh.maxFaces);
  limits->set_max_face_size(config.upload.mesh.maxFaceSize);
  limits->set_max_refined_vertices(config.upload.maxRefinedVertices);
  limits->set_min_relative_tolerance(config.tessellation.minRelativeTolerance);
  limits->set_min_pixel_accuracy(config.tessellation.minPixelAccuracy);
  limits->set_max_triangles(config.tessellation.maxTriangles);
  limits->set_max_uniform_level(config.tessellation.maxUniformLevel);
  limits->set_max_image_pixels(config.tessellation.maxImagePixels);
  limits->set_max_concurrent_jobs(config.maxConcurrentJobs);
  limits->set_max_queued_jobs(config.maxQueuedJobs);
  limits->set_memory_budget_bytes(config.memoryBudget);
  limits->set_job_memory_bytes(config.jobMemoryBytes);
  info.set_store(storeKind);
  info.set_auth_required(!config.token.empty());
  info.set_tls(!config.tlsCert.empty());
  info.set_tessellation_available(engine.available());
  return info;
}

void registerSampledMetrics(MetricsRegistry& registry, MeshRepository& repository,
                            const PatchSetCache& patches, AdmissionControl& admission,
                            const StreamWatch& streams) {
  registry.sampled("tessera_open_streams", "Streaming calls open.", "gauge",
                   [&] { return double(streams.openCalls()); });
  registry.sampled("tessera_streams_cancelled_total",
                   "Streaming calls cancelled because their client sent or read nothing for too long.",
                   "counter", [&] { return double(streams.cancelledCalls()); });
  registry.sampled("tessera_cache_hits_total", "Mesh cache lookups that found the mesh.",
                   "counter", [&] { return double(repository.cacheStats().hits); });
  registry.sampled("tessera_cache_misses_total", "Mesh cache lookups that had to load it.",
                   "counter", [&] { return double(repository.cacheStats().misses); });
  registry.sampled("tessera_cache_bytes", "Bytes of decoded meshes in the cache.", "gauge",
                   [&] { return double(repository.cacheStats().bytes); });
  registry.sampled("tessera_patch_cache_hits_total",
                   "Patch-set cache lookups that found the mesh's content preprocessed (cached, "
                   "or by the build they waited for).",
                   "counter", [&] { return double(patches.stats().hits); });
  registry.sampled("tessera_patch_cache_misses_total",
                   "Preprocessings the patch-set cache started (finished or not).", "counter",
                   [&] { return double(patches.stats().misses); });
  registry.sampled("tessera_patch_cache_bytes", "Bytes of preprocessed patch sets and mesh topologies in the cache.",
                   "gauge", [&] { return double(patches.stats().bytes); });
  registry.sampled("tessera_topology_cache_hits_total",
                   "Preprocessings that reused the topology of a mesh with the same faces, tags and rules "
                   "(an edit that moved vertices).",
                   "counter", [&] { return double(patches.topologyStats().hits); });
  registry.sampled("tessera_topology_cache_misses_total", "Topologies preprocessing built (OpenSubdiv's refinement and the pieces' layout).",
                   "counter", [&] { return double(patches.topologyStats().misses); });
  registry.sampled("tessera_patch_cache_evictions_total",
                   "Patch sets and topologies the patch-set cache dropped to make room (a later request for one preprocesses again).",
                   "counter", [&] { return double(patches.stats().evictions); });
  registry.sampled("tessera_queue_depth", "Heavy jobs waiting for admission, in both lanes.", "gauge",
                   [&] { return double(admission.queued()); });
  registry.sampled("tessera_jobs_running", "Heavy jobs admitted and running, in both lanes.", "gauge",
                   [&] { return double(admission.running()); });
  registry.sampled("tessera_light_queue_depth", "Light jobs waiting for the light lane's slots.", "gauge",
                   [&] { return double(admission.queued(AdmissionLane::kLight)); });
  registry.sampled("tessera_light_jobs_running", "Light jobs running in the light lane.", "gauge",
                   [&] { return double(admission.running(AdmissionLane::kLight)); });
  registry.sampled("tessera_memory_budget_bytes", "Memory the jobs together may reserve (--memory-budget less the caches).",
                   "gauge", [&] { return double(admission.memoryBudget()); });
  registry.sampled("tessera_memory_reserved_bytes", "Memory the running jobs have reserved.", "gauge",
                   [&] { return double(admission.memoryReserved()); });
  registry.sampled("tessera_admission_rejections_total",
                   "Jobs refused with RESOURCE_EXHAUSTED: the queue was full, or their memory did not fit.", "counter",
                   [&] { return double(admission.rejected()); });
  registry.sampled("tessera_store_bytes", "Bytes of mesh content in the store.", "gauge",
                   [&] { return double(repository.storeStats().storedBytes); });
  registry.sampled("tessera_store_meshes", "Meshes in the store.", "gauge",
                   [&] { return double(repository.storeStats().meshCount); });
}

// Written via a temporary file and a rename, so a reader never sees half of it.
void writeReadyFile(const std::string& path, const std::string& grpcAddress,
                    const std::string& metricsAddress, const std::string& httpAddress) {
  std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary);
    out << "grpc=" << grpcAddress << "\n";
    if (!metricsAddress.empty()) out << "metrics=" << metricsAddress << "\n";
    if (!httpAddress.empty()) out << "http=" << httpAddress << "\n";
    if (!out) throw std::runtime_error("--ready-file: cannot write " + temporary);
  }
  std::filesystem::rename(temporary, path);
}

std::string boundAddress(const std::string& listen, int port) {
  auto [host, ignored] = splitHostPort(listen, "--listen");
  return host.find(':') != std::string::npos ? fmt::format("[{}]:{}", host, port)
                                             : fmt::format("{}:{}", host, port);
}

// Removes gRPC's reflection service from a server being built.
class WithoutReflection : public grpc::ServerBuilderOption {
 public:
  void UpdateArguments(grpc::ChannelArguments*) override {}
  void UpdatePlugins(std::vector<std::unique_ptr<grpc::ServerBuilderPlugin>>* plugins) override {
    std::erase_if(*plugins, [](const auto& plugin) { return plugin->name() == "proto_server_reflection"; });
  }
};

// A service to register and the name health checks ask for it by.
struct NamedService {
  grpc::Service* service;
  const char* name;
};

// `reflectionV1`: served with gRPC's own v1alpha reflection; null when reflection is off.
std::unique_ptr<grpc::Server> startGrpcServer(const ServerConfig& config,
                                              const std::vector<NamedService>& services,
                                              ReflectionV1* reflectionV1, ServerMetrics& metrics, int* port) {
  grpc::EnableDefaultHealthCheckService(true);
  // Linking gRPC's reflection library registers its plugin for every builder at load time, so
  // "off" must take the plugin out again.
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  if (reflectionV1 == nullptr) builder.SetOption(std::make_unique<WithoutReflection>());
  builder.AddListeningPort(config.listen, serverCredentials(config), port);
  for (const NamedService& named : services) builder.RegisterService(named.service);
  if (reflectionV1 != nullptr) builder.RegisterService(reflectionV1);
  grpc::ResourceQuota quota("tessera-server");
  quota.SetMaxThreads(kMaxServerThreads);
  builder.SetResourceQuota(quota);
  std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> observers;
  observers.push_back(std::make_unique<RequestObserverFactory>(metrics, logFormatNamed(config.logFormat)));
  builder.experimental().SetInterceptorCreators(std::move(observers));
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server || *port == 0) return nullptr;
  // Health answers for the server ("") and for each service by name; later changes of the
  // serving status (the store's health, shutdown) apply to all of them.
  for (const NamedService& named : services) server->GetHealthCheckService()->SetServingStatus(named.name, true);
  server->GetHealthCheckService()->SetServingStatus(true);
  return server;
}

std::unique_ptr<MetricsHttpServer> startMetricsServer(const ServerConfig& config,
                                                      const MetricsRegistry& registry) {
  if (config.metricsListen == "off" || config.metricsListen.empty()) return nullptr;
  auto server = std::make_unique<MetricsHttpServer>(config.metricsListen,
                                                    [&registry] { return registry.render(); });
  server->start();
  return server;
}

// The HTTP front door over the server's own services (in process), when configured.
std::unique_ptr<HttpFrontDoor> startFrontDoor(const ServerConfig& config, grpc::Server& server) {
  if (config.httpListen == "off" || config.httpListen.empty()) return nullptr;
  auto frontDoor = std::make_unique<HttpFrontDoor>(
      HttpFrontDoorOptions{config.httpListen, config.httpCorsOrigin, kVersion, config.httpWebRoot},
      server.InProcessChannel(grpc::ChannelArguments()));
  frontDoor->start();
  return frontDoor;
}

// Load balancers and health-checking clients see NOT_SERVING first and, during the drain delay,
// stop sending; new calls are refused after it, and running ones get the grace period to finish.
// Without the delay, a call that reaches gRPC as it shuts down is cancelled before any handler
// sees it (its client gets CANCELLED, which it cannot tell from its own cancellation).
void shutDown(grpc::Server& server, double drainSeconds, double graceSeconds) {
  server.GetHealthCheckService()->SetServingStatus(false);
  std::this_thread::sleep_for(std::chrono::duration<double>(drainSeconds));
  auto grace = std::chrono::duration_cast<std::chrono::milliseconds>(
      std::chrono::duration<double>(graceSeconds));
  server.Shutdown(std::chrono::system_clock::now() + grace);
  server.Wait();
}

// Every call has ended and every store write is committed when the server has stopped; what is
// left is tearing down objects. gRPC's part of it (grpc_shutdown joining its executor threads as
// the last server object goes) took up to 16 s after a SIGTERM that cancelled long Tessellates
// on this 2-core VM (1 run in 4; bench/RUNAWAY-RESULTS.md), past the drain delay + 5 s the
// server promises. So the teardown gets a moment, then the process ends as it is (what a SIGKILL
// would leave, which the store survives: crash_recovery_test.cpp). A quarter of a second: the jobs
// cancelled at the grace's end take most of the second the promise leaves after it.
void exitSoonAfterStopping() {
  std::thread([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    spdlog::warn("teardown still running 0.25 s after stopping; exiting without it");
    spdlog::default_logger()->flush();
    std::_Exit(0);
  }).detach();
}

int waitForStopSignal(const sigset_t& signals) {
  int received = 0;
  while (sigwait(&signals, &received) != 0) {
  }
  return received;
}

}  // namespace

int runServer(const ServerConfig& config) {
  // Blocked here, before any thread starts, so that every thread inherits the mask and the
  // signals reach only sigwait() below.
  sigset_t stopSignals;
  sigemptyset(&stopSignals);
  sigaddset(&stopSignals, SIGINT);
  sigaddset(&stopSignals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stopSignals, nullptr);
  // A client that closes its connection while a response is being written must cost only that
  // response: cpp-httplib writes without MSG_NOSIGNAL, so SIGPIPE would end the process.
  std::signal(SIGPIPE, SIG_IGN);

  std::unique_ptr<MeshStore> store = openMeshStore(
      config.store, std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::duration<double>(config.storeTimeoutSeconds)));
  MetricsRegistry registry;
  ServerMetrics metrics(registry);
  MeshRepository repository(*store, static_cast<size_t>(config.cacheBytes));
  AdmissionControl admission(config.maxConcurrentJobs, config.maxQueuedJobs, config.jobMemoryBytes,
                             fmt::format("--memory-budget {} less the caches' {} and the server's own {}",
                                         formatBytes(config.memoryBudget),
                                         formatBytes(config.cacheBytes + config.patchCacheBytes),
                                         formatBytes(kServerBaseBytes)),
                             config.lightJobs);
  StreamWatch streams(StreamWatch::Limits{
      config.maxOpenStreams,
      std::chrono::duration_cast<StreamWatch::Clock::duration>(std::chrono::duration<double>(config.streamIdleSeconds)),
      std::chrono::duration_cast<StreamWatch::Clock::duration>(std::chrono::duration<double>(config.sessionIdleSeconds))});
  PatchSetCache patches(static_cast<size_t>(config.patchCacheBytes), config.upload.maxRefinedVertices);
  std::unique_ptr<TessellationEngine> engine = makeEngine(config, patches);
  // Probed now so that GetServerInfo can name the device; the renderer itself is created by the
  // first frame.
  std::unique_ptr<RenderBackend> renderer =
      makeRenderBackend(patches, /*probeDevice=*/true);
  BearerAuth auth(config.token);
  registerSampledMetrics(registry, repository, patches, admission, streams);
  registerProcessMetrics(registry);
  registerEngineMetrics(registry, *engine);

  MeshServiceImpl meshService(repository, admission, streams, auth, config.upload, metrics, patches);
  TessellationServiceImpl tessellationService(repository, admission, streams, *engine, auth,
                                              config.tessellation, metrics, config.lightJobTriangles);
  RenderServiceImpl renderService(repository, admission, streams, *renderer, auth, config.tessellation,
                                  registry);
  ServerInfoServiceImpl infoService(describeServer(config, *engine, *renderer, store->kind()),
                                    auth);

  // Reflection cannot be put behind the bearer token, so a server with a token does not offer it.
  bool reflection = config.reflection && config.token.empty();
  const std::vector<NamedService> services = {
      {&meshService, tessera::v1::MeshService::service_full_name()},
      {&tessellationService, tessera::v1::TessellationService::service_full_name()},
      {&renderService, tessera::v1::RenderService::service_full_name()},
      {&infoService, tessera::v1::ServerInfoService::service_full_name()}};
  std::vector<std::string> serviceNames = {"grpc.health.v1.Health", "grpc.reflection.v1.ServerReflection",
                                           "grpc.reflection.v1alpha.ServerReflection"};
  for (const NamedService& named : services) serviceNames.push_back(named.name);
  ReflectionV1 reflectionV1(std::move(serviceNames));
  int port = 0;
  std::unique_ptr<grpc::Server> server =
      startGrpcServer(config, services, reflection ? &reflectionV1 : nullptr, metrics, &port);
  if (!server) {
    spdlog::critical("cannot listen on {}", config.listen);
    return 1;
  }
  std::unique_ptr<MetricsHttpServer> metricsServer = startMetricsServer(config, registry);
  std::unique_ptr<HttpFrontDoor> frontDoor = startFrontDoor(config, *server);
  std::string address = boundAddress(config.listen, port);
  spdlog::info("tessera-server {} listening on {} (store {}, {} TLS, auth {}, reflection {}, "
               "metrics {}, http {})",
               kVersion, address, store->kind(), config.tlsCert.empty() ? "no" : "with",
               auth.enabled() ? "on" : "off", reflection ? "on" : "off",
               metricsServer ? metricsServer->address() : "off", frontDoor ? frontDoor->address() : "off");
  spdlog::info("memory budget {}: {} for jobs, {} for the caches", formatBytes(config.memoryBudget),
               formatBytes(config.jobMemoryBytes), formatBytes(config.cacheBytes + config.patchCacheBytes));
  spdlog::info("tessellation engine {}: {}{}", engine->name(), engine->detail(),
               engine->device().empty() ? "" : "; device " + engine->device());
  if (!auth.enabled() && !listensOnLoopbackOnly(config.listen)) {
    spdlog::warn("{} is reachable from other machines and no --token is set: anyone who can "
                 "connect may upload, read and delete meshes",
                 address);
  }
  if (frontDoor && !auth.enabled() && !listensOnLoopbackOnly(config.httpListen)) {
    spdlog::warn("the HTTP front door {} is reachable from other machines and no --token is set",
                 frontDoor->address());
  }
  // Health follows the store from now on (NOT_SERVING while it cannot serve).
  std::optional<StoreHealth> storeHealth;
  storeHealth.emplace(
      *store, [&server](bool serving) { server->GetHealthCheckService()->SetServingStatus(serving); },
      StoreHealth::Timing{});
  if (!config.readyFile.empty()) {
    writeReadyFile(config.readyFile, address, metricsServer ? metricsServer->address() : "",
                   frontDoor ? frontDoor->address() : "");
  }

  int signal = waitForStopSignal(stopSignals);
  spdlog::info("signal {} received: shutting down", signal);
  storeHealth.reset();  // no probe may report SERVING while the server drains
  if (frontDoor) frontDoor->stop();  // before the services it calls go
  shutDown(*server, config.drainDelaySeconds, config.shutdownGraceSeconds);
  if (metricsServer) metricsServer->stop();
  spdlog::info("stopped");
  exitSoonAfterStopping();
  return 0;
}

}  // namespace tessera::server
