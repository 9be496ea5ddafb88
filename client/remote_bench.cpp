#include "client/remote_bench.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <ctime>
#include <fstream>
#include <iostream>
#include <set>

#include "client/remote_bench_calls.h"
#include "client/remote_bench_cold.h"
#include "client/remote_bench_report.h"
#include "client/remote_bench_runner.h"
#include "client/remote_cold_copies.h"

namespace tessera::cli {
namespace {

namespace v1 = tessera::v1;

// Bounds that hold when a flag leaves them open: a level given only a duration stops after this
// many requests (the samples stay in memory), one given only a count stops after this long.
constexpr int64_t kMaxRequestsPerLevel = 1'000'000;
constexpr double kDefaultLevelLimitSeconds = 300;
constexpr int64_t kDefaultRequests = 1000;
constexpr int kDefaultRateWorkers = 32;
constexpr int kMaxWorkers = 1024;
// Setting up: connecting each channel, asking for server info and the meshes.
constexpr auto kSetupTimeout = std::chrono::seconds(10);

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A setup call failed; the exit code was reported with the message.
struct SetupFailure {
  int exitCode;
};

struct BenchFlags {
  std::string mix = "tessellate=1";
  std::vector<std::string> meshes;
  double tolerance = 0;
  bool relative = false;
  int level = 0;
  double eta = 0;
  int64_t maxTriangles = 0;
  std::vector<int> concurrency{1, 2, 4, 8, 16, 32};
  std::vector<std::string> rates;
  int64_t requests = 0;
  std::string duration;
  int64_t warmup = 0;
  std::string timeout = "60s";
  bool sharedChannel = false;
  bool noVerify = false;
  int64_t cold = 0;
  int coldSeed = 0;
  std::string json;
  CLI::App* command = nullptr;  // to ask which flags were given

  bool given(const char* flag) const { return command->get_option(flag)->count() > 0; }
};

// What the flags mean, checked.
struct BenchPlan {
  std::vector<std::pair<BenchOp, int>> mix;
  std::vector<BenchOp> schedule;
  std::vector<LoadLevel> levels;
  PhaseLimits limits;
  int64_t warmup = 0;
  BenchRequests requests;
  std::vector<std::string> meshNames;
  int64_t cold = 0;                     // cold requests per level (0: the mix)
  std::vector<ColdSource> coldSources;  // read back from the server at setup
};

double parseNumber(std::string_view text, const char* flag) {
  double value = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !(value > 0)) {
    throw UsageError(fmt::format("{} expects a positive number (got \"{}\")", flag, text));
  }
  return value;
}

// "30s", "500ms", "2m", or plain seconds.
std::chrono::duration<double> parseDuration(std::string_view text, const char* flag) {
  double scale = 1;
  if (text.ends_with("ms")) {
    scale = 1e-3, text.remove_suffix(2);
  } else if (text.ends_with("s")) {
    text.remove_suffix(1);
  } else if (text.ends_with("m")) {
    scale = 60, text.remove_suffix(1);
  }
  return std::chrono::duration<double>(parseNumber(text, flag) * scale);
}

std::vector<std::string> splitList(std::string_view text) {
  std::vector<std::string> parts;
  while (!text.empty()) {
    size_t comma = text.find(',');
    parts.emplace_back(text.substr(0, comma));
    text = comma == std::string_view::npos ? "" : text.substr(comma + 1);
  }
  return parts;
}

std::vector<std::pair<BenchOp, int>> parseMix(const std::string& text) {
  std::vector<std::pair<BenchOp, int>> mix;
  std::set<BenchOp> seen;
  for (const std::string& part : splitList(text)) {
    size_t eq = part.find('=');
    std::optional<BenchOp> op = mixOpFromName(part.substr(0, eq));
    int weight = 1;
    if (eq != std::string::npos) {
      std::string_view w = std::string_view(part).substr(eq + 1);
      auto [end, error] = std::from_chars(w.data(), w.data() + w.size(), weight);
      if (error != std::errc() || end != w.data() + w.size()) weight = -1;
    }
    if (!op || weight < 0 || weight > 1000 || !seen.insert(*op).second) {
      throw UsageError(fmt::format(
          "--mix expects OP=WEIGHT,... with OP one of tessellate, get, list, info (each once) "
          "and WEIGHT 0 to 1000 (got \"{}\")",
          part));
    }
    if (weight > 0) mix.emplace_back(*op, weight);
  }
  if (mix.empty()) throw UsageError("--mix needs at least one operation with a weight above 0");
  return mix;
}

bool mixHas(const std::vector<std::pair<BenchOp, int>>& mix, BenchOp op) {
  return std::any_of(mix.begin(), mix.end(), [op](const auto& entry) { return entry.first == op; });
}

v1::TessellateRequest tessellateRequest(const BenchFlags& flags, const std::string& mesh) {
  v1::TessellateRequest request;
  request.set_name(mesh);
  if (flags.tolerance > 0) {
    flags.relative ? request.set_relative(flags.tolerance) : request.set_absolute(flags.tolerance);
  }
  if (flags.level > 0) request.set_uniform_level(flags.level);
  if (flags.given("--eta")) request.set_eta(flags.eta);
  if (flags.given("--max-triangles")) request.set_max_triangles(flags.maxTriangles);
  return request;
}

std::vector<LoadLevel> parseLevels(const BenchFlags& flags) {
  std::vector<LoadLevel> levels;
  auto checkWorkers = [](int workers) {
    if (workers < 1 || workers > kMaxWorkers) {
      throw UsageError(fmt::format("--concurrency expects 1 to {} (got {})", kMaxWorkers, workers));
    }
  };
  if (flags.rates.empty()) {
    for (int workers : flags.concurrency) {
      checkWorkers(workers);
      levels.push_back({workers, std::nullopt});
    }
    return levels;
  }
  if (flags.given("--concurrency") && flags.concurrency.size() != 1) {
    throw UsageError("with --rate, --concurrency is one number: the most requests in flight");
  }
  int workers = flags.given("--concurrency") ? flags.concurrency.front() : kDefaultRateWorkers;
  checkWorkers(workers);
  for (const std::string& rate : flags.rates) {
    std::string_view text = rate;
    if (text.ends_with("/s")) text.remove_suffix(2);
    levels.push_back({workers, parseNumber(text, "--rate")});
  }
  return levels;
}

BenchPlan makePlan(const BenchFlags& flags) {
  BenchPlan plan;
  plan.mix = parseMix(flags.mix);
  plan.schedule = interleaveMix(plan.mix);
  plan.levels = parseLevels(flags);
  if (flags.cold < 0 || flags.cold > kMaxRequestsPerLevel) {
    throw UsageError(fmt::format("--cold expects 1 to {} meshes", kMaxRequestsPerLevel));
  }
  plan.cold = flags.cold;
  const bool tessellates = plan.cold > 0 || mixHas(plan.mix, BenchOp::kTessellate);
  if ((tessellates || mixHas(plan.mix, BenchOp::kGet)) && flags.meshes.empty()) {
    throw UsageError("--mesh meshes/NAME is required for tessellate, get and --cold");
  }
  for (const std::string& mesh : flags.meshes) plan.meshNames.push_back(asMeshName(mesh));
  if (tessellates) {
    if (flags.tolerance <= 0 && flags.level <= 0) {
      throw UsageError(
          "tessellate needs --tolerance E (with --relative for a fraction of the "
          "diagonal) or --level P");
    }
  }
  if (flags.relative && flags.tolerance <= 0) throw UsageError("--relative needs --tolerance");
  for (const std::string& mesh : plan.meshNames) {
    plan.requests.tessellate.push_back(tessellateRequest(flags, mesh));
    plan.requests.get.emplace_back().set_name(mesh);
  }
  plan.requests.list.set_page_size(50);
  plan.requests.verifyChecksum = !flags.noVerify;
  plan.requests.timeout = std::chrono::duration_cast<std::chrono::milliseconds>(
      parseDuration(flags.timeout, "--timeout"));
  if (flags.requests < 0 || flags.warmup < 0) {
    throw UsageError("--requests and --warmup must not be negative");
  }
  const bool haveDuration = !flags.duration.empty();
  plan.limits.requests = plan.cold > 0        ? plan.cold
                         : flags.requests > 0 ? std::min(flags.requests, kMaxRequestsPerLevel)
                         : haveDuration       ? kMaxRequestsPerLevel
                                              : kDefaultRequests;
  plan.limits.duration = haveDuration ? parseDuration(flags.duration, "--duration")
                                      : std::chrono::duration<double>(kDefaultLevelLimitSeconds);
  plan.warmup = std::min(flags.warmup, kMaxRequestsPerLevel);
  return plan;
}

grpc::ChannelArguments ownConnection() {
  grpc::ChannelArguments arguments;
  // Without this, channels to the same address with the same arguments share one connection.
  arguments.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  return arguments;
}

std::shared_ptr<grpc::Channel> connect(const RemoteEndpoint& endpoint) {
  auto channel = makeChannel(endpoint, ownConnection());
  if (!channel->WaitForConnected(std::chrono::system_clock::now() + kSetupTimeout)) {
    std::cerr << fmt::format("tessera bench: cannot connect to {}\n", endpoint.server);
    throw SetupFailure{kExitRemote};
  }
  return channel;
}

template <typename Call>
void setupCall(const RemoteEndpoint& endpoint, const std::string& what, Call call) {
  grpc::ClientContext context;
  prepareContext(context, endpoint, kSetupTimeout);
  grpc::Status status = call(context);
  if (!status.ok()) throw SetupFailure{reportRpcError(what, status, &context)};
}

// Reads the run's meshes back for the cold mix to copy.
std::vector<ColdSource> readColdSources(const RemoteEndpoint& endpoint, v1::MeshService::Stub& stub,
                                        const BenchPlan& plan) {
  std::vector<ColdSource> sources(plan.meshNames.size());
  for (size_t k = 0; k < sources.size(); ++k) {
    setupCall(endpoint, "bench: download " + plan.meshNames[k], [&](grpc::ClientContext& c) {
      return readColdSource(stub, c, plan.meshNames[k], &sources[k]);
    });
  }
  return sources;
}

// Checks that the server answers and knows the meshes before any load is applied.
v1::ServerInfo checkServer(const RemoteEndpoint& endpoint, BenchPlan& plan) {
  auto channel = connect(endpoint);
  v1::ServerInfo info;
  auto infoStub = v1::ServerInfoService::NewStub(channel);
  setupCall(endpoint, "bench: info", [&](grpc::ClientContext& c) {
    return infoStub->GetServerInfo(&c, v1::GetServerInfoRequest(), &info);
  });
  auto meshStub = v1::MeshService::NewStub(channel);
  for (const v1::GetMeshRequest& request : plan.requests.get) {
    v1::Mesh mesh;
    setupCall(endpoint, "bench: get " + request.name(),
              [&](grpc::ClientContext& c) { return meshStub->GetMesh(&c, request, &mesh); });
  }
  if (plan.cold > 0) plan.coldSources = readColdSources(endpoint, *meshStub, plan);
  return info;
}

std::string describeMix(const std::vector<std::pair<BenchOp, int>>& mix) {
  std::string text;
  for (const auto& [op, weight] : mix) {
    text += fmt::format("{}{}={}", text.empty() ? "" : ",", benchOpName(op), weight);
  }
  return text;
}

std::string describeRequest(const BenchFlags& flags, const BenchPlan& plan) {
  if (plan.cold == 0 && !mixHas(plan.mix, BenchOp::kTessellate)) return "no tessellations";
  if (flags.level > 0) return fmt::format("uniform level {}", flags.level);
  return fmt::format("{} tolerance {:g}", flags.relative ? "relative" : "absolute",
                     flags.tolerance);
}

std::string utcNow() {
  std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

void printPreamble(const BenchFlags& flags, const BenchPlan& plan, const RemoteEndpoint& endpoint,
                   const v1::ServerInfo& info) {
  std::cout << fmt::format("tessera bench: {} (tessera {}, {} store, {})\n", endpoint.server,
                           info.version(), info.store(), info.device());
  std::string meshes;
  for (const std::string& mesh : plan.meshNames) meshes += (meshes.empty() ? "" : ", ") + mesh;
  if (plan.cold > 0) {
    std::cout << fmt::format(
        "cold: per level {} uploads of meshes the server has not seen (copies of {}, every vertex "
        "moved "
        "by up to {:g} of the diagonal; ids {}...), each tessellated once at {}\n",
        plan.cold, meshes, kColdDisplacement, coldMeshId(flags.coldSeed, 0),
        describeRequest(flags, plan));
  } else {
    std::cout << fmt::format("mix {}; meshes {}; {}\n", describeMix(plan.mix),
                             meshes.empty() ? "none" : meshes, describeRequest(flags, plan));
  }
  std::cout << fmt::format(
      "per level: {} requests or {:g} s, whichever first; warmup {}; deadline {:g} s per call; "
      "{}; checksums {}\n",
      plan.limits.requests, plan.limits.duration.count(), plan.warmup,
      plan.requests.timeout.count() / 1e3,
      flags.sharedChannel ? "one shared channel" : "a channel (connection) per worker",
      plan.requests.verifyChecksum ? "verified" : "not verified");
  int most = 0;
  for (const LoadLevel& level : plan.levels) most = std::max(most, level.workers);
  const v1::ServerLimits& limits = info.limits();
  const int admitted = limits.max_concurrent_jobs() + limits.max_queued_jobs();
  if ((plan.cold > 0 || mixHas(plan.mix, BenchOp::kTessellate)) && most > admitted) {
    std::cout << fmt::format(
        "note: up to {} concurrent tessellations, but the server runs {} and queues {}: expect "
        "RESOURCE_EXHAUSTED (server busy) past that\n",
        most, limits.max_concurrent_jobs(), limits.max_queued_jobs());
  }
  std::cout << "\n";
}

nlohmann::json runJson(const BenchFlags& flags, const BenchPlan& plan,
                       const RemoteEndpoint& endpoint, const v1::ServerInfo& info) {
  nlohmann::json mix = nlohmann::json::object();
  for (const auto& [op, weight] : plan.mix) mix[std::string(benchOpName(op))] = weight;
  nlohmann::json request = nlohmann::json::object();
  if (flags.tolerance > 0) request[flags.relative ? "relative" : "absolute"] = flags.tolerance;
  if (flags.level > 0) request["uniform_level"] = flags.level;
  if (flags.given("--eta")) request["eta"] = flags.eta;
  nlohmann::json cold = nullptr;
  if (plan.cold > 0) {
    cold = {{"meshes_per_level", plan.cold},
            {"seed", flags.coldSeed},
            {"first_id", coldMeshId(flags.coldSeed, 0)},
            {"displacement_of_diagonal", kColdDisplacement}};
    mix = nullptr;
  }
  return {{"tool", "tessera bench"},
          {"started", utcNow()},
          {"server", endpoint.server},
          {"server_version", info.version()},
          {"server_store", info.store()},
          {"server_device", info.device()},
          {"mode", flags.rates.empty() ? "concurrency" : "rate"},
          {"channels", flags.sharedChannel ? "shared" : "per-worker"},
          {"mix", mix},
          {"cold", cold},
          {"meshes", plan.meshNames},
          {"tessellate_request", request},
          {"requests_per_level", plan.limits.requests},
          {"duration_limit_s", plan.limits.duration.count()},
          {"warmup", plan.warmup},
          {"timeout_s", plan.requests.timeout.count() / 1e3},
          {"verify_checksum", plan.requests.verifyChecksum},
          {"levels", nlohmann::json::array()}};
}

// One BenchClient per worker, each on its own channel unless shared.
std::vector<std::unique_ptr<BenchClient>> makeClients(const BenchFlags& flags,
                                                      const BenchPlan& plan,
                                                      const RemoteEndpoint& endpoint) {
  int workers = 0;
  for (const LoadLevel& level : plan.levels) workers = std::max(workers, level.workers);
  std::vector<std::unique_ptr<BenchClient>> clients;
  std::shared_ptr<grpc::Channel> shared = flags.sharedChannel ? connect(endpoint) : nullptr;
  for (int w = 0; w < workers; ++w) {
    auto channel = shared ? shared : connect(endpoint);
    clients.push_back(std::make_unique<BenchClient>(channel, endpoint, plan.requests));
  }
  return clients;
}

int runBench(const BenchFlags& flags, const RemoteEndpoint& endpoint) {
  BenchPlan plan;
  try {
    plan = makePlan(flags);
  } catch (const UsageError& e) {
    std::cerr << "tessera bench: " << e.what() << "\n";
    return kExitUsage;
  }
  v1::ServerInfo info;
  std::vector<std::unique_ptr<BenchClient>> owned;
  try {
    info = checkServer(endpoint, plan);
    owned = makeClients(flags, plan, endpoint);
  } catch (const SetupFailure& failure) {
    return failure.exitCode;
  }
  std::vector<BenchClient*> clients;
  for (auto& client : owned) clients.push_back(client.get());

  printPreamble(flags, plan, endpoint, info);
  nlohmann::json json = runJson(flags, plan, endpoint, info);
  printTableHeader(std::cout, !flags.rates.empty());
  // Cold copies are numbered across the whole run, warm-ups included, so no two share content.
  int64_t nextCopy = 0;
  auto requestsOf = [&](const PhaseLimits& limits) {
    if (plan.cold == 0) return mixRequests(plan.schedule);
    PhaseRequest cold =
        coldRequests(plan.coldSources, plan.requests.tessellate, flags.coldSeed, nextCopy);
    nextCopy += limits.requests;
    return cold;
  };
  for (const LoadLevel& level : plan.levels) {
    if (plan.warmup > 0) {
      const PhaseLimits warmup{plan.warmup, plan.limits.duration};
      runPhase(clients, requestsOf(warmup), level, warmup);
    }
    LevelResult result =
        summarizeLevel(level, runPhase(clients, requestsOf(plan.limits), level, plan.limits));
    printLevel(std::cout, result, plan.mix.size() > 1 || plan.cold > 0);
    json["levels"].push_back(toJson(result));
  }
  if (!flags.json.empty()) {
    std::ofstream out(flags.json);
    out << json.dump(2) << "\n";
    if (!out) {
      std::cerr << fmt::format("tessera bench: cannot write {}\n", flags.json);
      return kExitIo;
    }
  }
  return kExitOk;
}

}  // namespace

void registerBenchCommand(CLI::App& app, CommandContext& context,
                          std::shared_ptr<const RemoteEndpoint> endpoint) {
  auto flags = std::make_shared<BenchFlags>();
  CLI::App* bench = app.add_subcommand(
      "bench", "Load-test the server: throughput, latency percentiles and errors per load level");
  flags->command = bench;
  bench->add_option("--mix", flags->mix, "Operations and weights: tessellate=8,get=1,list=1,info=1")
      ->capture_default_str();
  bench->add_option("--mesh", flags->meshes, "Stored mesh(es) to tessellate and get (round robin)")
      ->delimiter(',');
  bench->add_option("--tolerance", flags->tolerance, "Tessellation tolerance (object units)");
  bench->add_flag("--relative", flags->relative, "The tolerance is a fraction of the diagonal");
  bench->add_option("--level", flags->level, "Uniform tessellation level instead of a tolerance");
  bench->add_option("--eta", flags->eta, "Share of the tolerance for ring refinement (0..1)");
  bench->add_option("--max-triangles", flags->maxTriangles, "Triangle budget of each request");
  bench
      ->add_option("--concurrency", flags->concurrency,
                   "Workers per level (a sweep: 1,2,4,...); with --rate, the most in flight")
      ->delimiter(',')
      ->capture_default_str();
  bench->add_option("--rate", flags->rates, "Open loop: requests per second (R or R/s; a list)")
      ->delimiter(',');
  bench->add_option("--requests", flags->requests,
                    fmt::format("Requests per level (default {})", kDefaultRequests));
  bench->add_option(
      "--duration", flags->duration,
      fmt::format("Time limit per level, e.g. 30s (default {:g} s)", kDefaultLevelLimitSeconds));
  bench->add_option("--warmup", flags->warmup, "Requests before each level, not measured");
  bench->add_option("--timeout", flags->timeout, "Deadline of every call")->capture_default_str();
  bench->add_flag("--shared-channel", flags->sharedChannel,
                  "All workers on one channel (one connection) instead of one each");
  bench->add_flag("--no-verify", flags->noVerify, "Do not check each GLB's SHA-256");
  CLI::Option* cold = bench->add_option("--cold", flags->cold,
                                        "Cold mix instead: per level, N uploads of new content "
                                        "(copies of --mesh), each tessellated once");
  cold->excludes(bench->get_option("--mix"))->excludes(bench->get_option("--requests"));
  bench
      ->add_option("--cold-seed", flags->coldSeed,
                   "Numbers the cold copies (ids bench-cold-SEED-I); a server that has seen a seed "
                   "refuses its ids again")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  bench->add_option("--json", flags->json, "Also write the results as JSON to this file");
  bench->callback([&context, endpoint, flags] { context.exitCode = runBench(*flags, *endpoint); });
}

}  // namespace tessera::cli
