// tessera-soak: many clients mixing hostile, cold and normal requests against a running server for
// a while, with the server's memory watched throughout (issues 16 and 46, bench/SOAK-RESULTS.md,
// tools/soak.sh; a short run is the test Server.SoakTest.*).
//
//   tessera-soak --server 127.0.0.1:PORT --server-pid PID --models DIR [--clients 32] [--hostile 8]
//       [--cold 8] [--cold-models bigguy,...] [--cold-tolerance 1e-3] [--seconds 600] [--token T]
//       [--json FILE]
//
// Uploads the small and the large model (bigguy and armorguy by default) and the cold storm's
// models, then runs --clients clients on channels of their own for --seconds: --hostile of them
// send only hostile requests (soak_requests.h), --cold of them are the cold storm (uploads of
// meshes the server has never seen, copies of the cold models, each tessellated once), the
// others normal ones, retried after the server's pushback, whose patch sets are warm. Prints a
// Markdown report: the server's peak resident memory (the kernel's VmHWM) beside its memory
// budget, its resident memory before and after, every request kind's answers by status code,
// the normal requests' latency beside the storm, the cold uploads and first GLBs (how many, how
// many distinct contents, refusals, latency), and whether the server still serves a normal
// request at the end, and how soon after the clients' last answers the server's CPU is idle (each
// hostile client starts and ends with runaways: legitimately long Tessellates with a 1 s deadline, which
// the server must stop then). Exits 1 when a request ended with a code it may not end with or the
// last request failed.
#include <grpcpp/grpcpp.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tessera/status_names.h"
#include "tessera/v1/server_info.grpc.pb.h"
#include "tools/soak/soak_requests.h"

namespace {

namespace v1 = tessera::v1;
using tessera::soak::Outcome;
using tessera::soak::Role;
using tessera::soak::SoakClient;
using tessera::soak::SoakSetup;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string server, token, models, small = "bigguy", large = "armorguy", json;
  int serverPid = 0, clients = 32, hostile = 8, cold = 0, seed = 1;
  std::vector<std::string> coldModels{"bigguy", "monsterfrog", "car", "t-rex", "armorguy"};
  double coldTolerance = 1e-3;
  double seconds = 600;
};

// VmRSS or VmHWM of the server in bytes (-1 when it cannot be read).
int64_t serverMemory(int pid, const std::string& field) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind(field + ":", 0) == 0) return std::stoll(line.substr(field.size() + 1)) * 1024;
  }
  return -1;
}

// User plus system CPU seconds of the process (/proc/PID/stat fields 14 and 15), -1 if gone.
double cpuSeconds(int pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  const std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const size_t close = text.rfind(')');
  if (close == std::string::npos) return -1;
  std::istringstream fields(text.substr(close + 2));
  std::string field;
  long long ticks = 0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i >= 14) ticks += std::stoll(field);
  }
  return double(ticks) / double(sysconf(_SC_CLK_TCK));
}

// Seconds until the process uses under 10 % of a core over 300 ms; -1 after `limit` seconds.
double secondsUntilIdle(int pid, double limit) {
  const auto start = Clock::now();
  for (;;) {
    const auto from = Clock::now();
    const double before = cpuSeconds(pid);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const double window = std::chrono::duration<double>(Clock::now() - from).count();
    if (cpuSeconds(pid) - before < 0.1 * window) return std::chrono::duration<double>(from - start).count();
    if (std::chrono::duration<double>(Clock::now() - start).count() > limit) return -1;
  }
}

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The small mesh seen whole from +z, for the frames.
v1::Camera viewOf(const v1::Mesh& mesh) {
  const v1::BoundingBox& box = mesh.bounding_box();
  const double cx = (box.min().x() + box.max().x()) / 2, cy = (box.min().y() + box.max().y()) / 2,
               cz = (box.min().z() + box.max().z()) / 2;
  const double dx = box.max().x() - box.min().x(), dy = box.max().y() - box.min().y(),
               dz = box.max().z() - box.min().z();
  const double diagonal = std::sqrt(dx * dx + dy * dy + dz * dz);
  v1::Camera camera;
  camera.mutable_eye()->set_x(cx), camera.mutable_eye()->set_y(cy), camera.mutable_eye()->set_z(cz + 2 * diagonal);
  camera.mutable_target()->set_x(cx), camera.mutable_target()->set_y(cy), camera.mutable_target()->set_z(cz);
  camera.mutable_up()->set_y(1);
  camera.set_fov_y_deg(40);
  return camera;
}

// Uploads a model unless the server has it already; its metadata.
v1::Mesh ensureModel(v1::MeshService::Stub& stub, const Options& options, const std::string& model,
                     const std::string& text) {
  const std::string id = "soak-" + model;
  grpc::ClientContext upload;
  const grpc::Status uploaded = tessera::soak::uploadObj(stub, upload, options.token, id, text, 300);
  if (!uploaded.ok() && uploaded.error_code() != grpc::StatusCode::ALREADY_EXISTS) {
    throw std::runtime_error("uploading " + model + ": " + uploaded.error_message());
  }
  grpc::ClientContext context;
  tessera::soak::prepare(context, options.token, 300);
  v1::GetMeshRequest request;
  request.set_name("meshes/" + id);
  v1::Mesh mesh;
  const grpc::Status found = stub.GetMesh(&context, request, &mesh);
  if (!found.ok()) throw std::runtime_error("looking up " + id + ": " + found.error_message());
  return mesh;
}

v1::ServerInfo serverInfo(const std::shared_ptr<grpc::Channel>& channel, const std::string& token) {
  grpc::ClientContext context;
  tessera::soak::prepare(context, token, 300);
  v1::ServerInfo info;
  const grpc::Status status = v1::ServerInfoService::NewStub(channel)->GetServerInfo(&context, {}, &info);
  if (!status.ok()) throw std::runtime_error("GetServerInfo: " + status.error_message());
  return info;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, size_t(p * double(values.size())))];
}

double mib(int64_t bytes) { return double(bytes) / 1048576.0; }

struct Report {
  int64_t budget = 0, jobBudget = 0, rssBefore = 0, rssAfter = 0, peak = 0, peakSampled = 0;
  double idleAfterSeconds = -1;  // from the clients' last answer until the server's CPU is idle
  double runawayIdleAfterSeconds = -1;  // from the last runaway's answer until then
  double seconds = 0;
  std::vector<Outcome> outcomes;
  Outcome last;
};

// The cold storm's models, uploaded (as for the others, unless there) and read back to be copied.
std::vector<tessera::cli::ColdSource> coldSources(v1::MeshService::Stub& stub, const Options& options) {
  std::vector<tessera::cli::ColdSource> sources;
  for (const std::string& model : options.coldModels) {
    const v1::Mesh mesh =
        ensureModel(stub, options, model, readText(std::filesystem::path(options.models) / (model + ".obj")));
    grpc::ClientContext context;
    tessera::soak::prepare(context, options.token, 300);
    const grpc::Status read = tessera::cli::readColdSource(stub, context, mesh.name(), &sources.emplace_back());
    if (!read.ok()) throw std::runtime_error("reading back " + mesh.name() + ": " + read.error_message());
  }
  return sources;
}

constexpr auto kRunawayStretch = std::chrono::seconds(4);

// Each client's loop until the end time; outcomes kept per client, merged at the end.
std::vector<Outcome> runClients(const Options& options, const SoakSetup& setup) {
  std::vector<std::vector<Outcome>> perClient(size_t(options.clients));
  std::vector<std::thread> threads;
  const auto end = Clock::now() + std::chrono::milliseconds(int64_t(options.seconds * 1000));
  for (int c = 0; c < options.clients; ++c) {
    threads.emplace_back([&, c] {
      SoakClient client(grpc::CreateChannel(options.server, grpc::InsecureChannelCredentials()));
      client.random.seed(uint32_t(options.seed * 1000 + c));
      const Role role = c < options.hostile               ? Role::kHostile
                        : c < options.hostile + options.cold ? Role::kCold
                                                             : Role::kNormal;
      std::vector<Outcome>& outcomes = perClient[size_t(c)];
      for (uint64_t serial = 0; Clock::now() < end; ++serial) {
        if (role == Role::kCold) {
          for (Outcome& o : tessera::soak::coldRequest(client, setup, c, serial)) outcomes.push_back(std::move(o));
        } else {
          // A hostile client's first request and those in the last seconds are runaways, so that
          // the soak has them, and ends with them running (the CPU must go idle after: below).
          const bool runaway = serial == 0 || end - Clock::now() < kRunawayStretch;
          outcomes.push_back(role == Role::kHostile ? tessera::soak::hostileRequest(client, setup, c, serial, runaway)
                                                    : tessera::soak::normalRequest(client, setup));
        }
      }
    });
  }
  for (auto& thread : threads) thread.join();
  std::vector<Outcome> all;
  for (auto& outcomes : perClient) all.insert(all.end(), outcomes.begin(), outcomes.end());
  return all;
}

// The cold storm's uploads and first GLBs: how many, how many succeeded, how many distinct
// contents the server stored (each must be new, or the storm is not cold), refusals, latency.
nlohmann::json coldJson(const Options& options, const std::vector<Outcome>& outcomes) {
  int uploads = 0, glbs = 0, refused = 0;
  std::set<std::string> contents;
  std::vector<double> uploadMs, glbMs;
  for (const Outcome& o : outcomes) {
    if (o.role != Role::kCold) continue;
    const bool upload = o.kind == "cold upload";
    ++(upload ? uploads : glbs);
    if (o.code == grpc::StatusCode::RESOURCE_EXHAUSTED) ++refused;
    if (o.code != grpc::StatusCode::OK) continue;
    (upload ? uploadMs : glbMs).push_back(o.ms);
    if (upload) contents.insert(o.sha256);
  }
  return {{"clients", options.cold}, {"models", options.coldModels}, {"relative_tolerance", options.coldTolerance},
          {"uploads", uploads}, {"uploads_ok", uploadMs.size()}, {"distinct_contents", contents.size()},
          {"first_glbs", glbs}, {"first_glbs_ok", glbMs.size()}, {"refused", refused},
          {"upload_p50_ms", percentile(uploadMs, 0.5)}, {"upload_p99_ms", percentile(uploadMs, 0.99)},
          {"first_glb_p50_ms", percentile(glbMs, 0.5)}, {"first_glb_p99_ms", percentile(glbMs, 0.99)},
          {"first_glb_max_ms", percentile(glbMs, 1.0)}};
}

nlohmann::json toJson(const Options& options, const Report& report) {
  nlohmann::json out = {{"clients", options.clients}, {"hostile_clients", options.hostile},
                        {"cold_clients", options.cold},
                        {"seconds", report.seconds}, {"memory_budget_bytes", report.budget},
                        {"job_memory_bytes", report.jobBudget}, {"rss_before_bytes", report.rssBefore},
                        {"rss_after_bytes", report.rssAfter}, {"peak_rss_bytes", report.peak},
                        {"peak_rss_sampled_bytes", report.peakSampled},
                        {"server_idle_after_s", report.idleAfterSeconds},
                        {"runaway_idle_after_s", report.runawayIdleAfterSeconds},
                        {"last_request_ok", report.last.code == grpc::StatusCode::OK}};
  // Per request kind and answer: how many, and their total time.
  std::map<std::pair<std::string, std::string>, std::pair<int, double>> counts;
  std::vector<double> normalMs;
  int unexpected = 0, pushbacks = 0, normal = 0;
  nlohmann::json examples = nlohmann::json::array();
  for (const Outcome& o : report.outcomes) {
    std::string code(tessera::statusCodeName(o.code));
    if (o.pushedBack) code += " (busy)";
    auto& [count, ms] = counts[{o.kind, code}];
    ++count, ms += o.ms;
    pushbacks += o.pushbacks;
    if (o.role == Role::kNormal) ++normal;
    if (o.role == Role::kNormal && o.code == grpc::StatusCode::OK) normalMs.push_back(o.ms);
    if (o.expected) continue;
    ++unexpected;
    if (examples.size() < 10) {
      examples.push_back({{"kind", o.kind}, {"code", tessera::statusCodeName(o.code)}, {"message", o.message}});
    }
  }
  for (const auto& [key, value] : counts) {
    out["answers"].push_back(
        {{"kind", key.first}, {"code", key.second}, {"count", value.first}, {"mean_ms", value.second / value.first}});
  }
  out["normal"] = {{"requests", normal}, {"ok", normalMs.size()}, {"pushbacks", pushbacks},
                   {"p50_ms", percentile(normalMs, 0.5)}, {"p99_ms", percentile(normalMs, 0.99)},
                   {"max_ms", percentile(normalMs, 1.0)}};
  out["cold"] = coldJson(options, report.outcomes);
  out["unexpected"] = unexpected;
  out["unexpected_examples"] = examples;
  return out;
}

void printMarkdown(const nlohmann::json& r) {
  std::printf("- %d clients (%d hostile, %d cold) for %.0f s; memory budget %.0f MiB (%.0f MiB for jobs)\n",
              r["clients"].get<int>(), r["hostile_clients"].get<int>(), r["cold_clients"].get<int>(),
              r["seconds"].get<double>(), mib(r["memory_budget_bytes"]), mib(r["job_memory_bytes"]));
  std::printf("- server resident memory: %.0f MiB before, peak %.0f MiB (VmHWM; %.0f MiB sampled every 20 ms), "
              "%.0f MiB after\n",
              mib(r["rss_before_bytes"]), mib(r["peak_rss_bytes"]), mib(r["peak_rss_sampled_bytes"]),
              mib(r["rss_after_bytes"]));
  std::printf("- the server's CPU idle %.1f s after the clients' last answers, %.1f s after a last runaway's "
              "deadline (-1: still busy after 30 s)\n",
              r["server_idle_after_s"].get<double>(), r["runaway_idle_after_s"].get<double>());
  const auto& n = r["normal"];
  std::printf("- normal (warm) requests: %d, %d OK, %d pushbacks waited out; latency of the OK ones (pushbacks "
              "included) p50 %.1f ms, p99 %.1f ms, max %.1f ms\n",
              n["requests"].get<int>(), n["ok"].get<int>(), n["pushbacks"].get<int>(), n["p50_ms"].get<double>(),
              n["p99_ms"].get<double>(), n["max_ms"].get<double>());
  const auto& c = r["cold"];
  if (c["clients"].get<int>() > 0) {
    std::printf("- cold storm (copies of the cold models at relative %g): %d uploads, %d OK, %d distinct contents; "
                "%d first GLBs, %d OK; %d refused RESOURCE_EXHAUSTED; upload p50 %.1f ms, p99 %.1f ms; first GLB "
                "p50 %.1f ms, p99 %.1f ms, max %.1f ms\n",
                c["relative_tolerance"].get<double>(), c["uploads"].get<int>(), c["uploads_ok"].get<int>(),
                c["distinct_contents"].get<int>(), c["first_glbs"].get<int>(), c["first_glbs_ok"].get<int>(),
                c["refused"].get<int>(), c["upload_p50_ms"].get<double>(), c["upload_p99_ms"].get<double>(),
                c["first_glb_p50_ms"].get<double>(), c["first_glb_p99_ms"].get<double>(),
                c["first_glb_max_ms"].get<double>());
  }
  std::printf("- answers with a code the request may not end with: %d; a normal request after the soak: %s\n\n",
              r["unexpected"].get<int>(), r["last_request_ok"].get<bool>() ? "OK" : "failed");
  std::printf("| request | answer | count | mean ms |\n|---|---|---:|---:|\n");
  for (const auto& a : r["answers"]) {
    std::printf("| %s | %s | %d | %.1f |\n", a["kind"].get<std::string>().c_str(), a["code"].get<std::string>().c_str(),
                a["count"].get<int>(), a["mean_ms"].get<double>());
  }
  for (const auto& e : r["unexpected_examples"]) {
    std::printf("\nunexpected: %s %s: %s\n", e["kind"].get<std::string>().c_str(),
                e["code"].get<std::string>().c_str(), e["message"].get<std::string>().c_str());
  }
}

int run(const Options& options) {
  auto channel = grpc::CreateChannel(options.server, grpc::InsecureChannelCredentials());
  const v1::ServerInfo info = serverInfo(channel, options.token);
  auto meshes = v1::MeshService::NewStub(channel);
  SoakSetup setup;
  setup.token = options.token;
  setup.renderAvailable = info.backends_size() > 1 && info.backends(1).available();
  setup.smallObj = readText(std::filesystem::path(options.models) / (options.small + ".obj"));
  const v1::Mesh small = ensureModel(*meshes, options, options.small, setup.smallObj);
  ensureModel(*meshes, options, options.large, readText(std::filesystem::path(options.models) / (options.large + ".obj")));
  setup.smallMesh = "meshes/soak-" + options.small;
  setup.largeMesh = "meshes/soak-" + options.large;
  setup.smallView = viewOf(small);
  setup.seed = options.seed;
  setup.coldTolerance = options.coldTolerance;
  if (options.cold > 0) setup.coldSources = coldSources(*meshes, options);

  // The patch sets built and cached before memory is first measured.
  SoakClient warm(channel);
  tessera::soak::warmUp(warm, setup);

  Report report;
  report.budget = info.limits().memory_budget_bytes();
  report.jobBudget = info.limits().job_memory_bytes();
  report.rssBefore = serverMemory(options.serverPid, "VmRSS");
  std::atomic<bool> sampling{true};
  std::thread sampler([&] {
    while (sampling) {
      report.peakSampled = std::max(report.peakSampled, serverMemory(options.serverPid, "VmRSS"));
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  const auto start = Clock::now();
  report.outcomes = runClients(options, setup);
  report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  sampling = false;
  sampler.join();
  // Every call has ended for its client (the runaways at their deadlines): the server must
  // stop their work too (issue 47), so its CPU goes idle.
  report.idleAfterSeconds = secondsUntilIdle(options.serverPid, 30);
  // And one more, alone, whose end is the CPU's only cause to go idle.
  SoakClient runaway(channel);
  report.outcomes.push_back(tessera::soak::lastRunaway(runaway, setup));
  report.runawayIdleAfterSeconds = secondsUntilIdle(options.serverPid, 30);
  // Calls the clients abandoned end on the server within moments; then memory is measured.
  std::this_thread::sleep_for(std::chrono::seconds(3));
  report.rssAfter = serverMemory(options.serverPid, "VmRSS");
  report.peak = serverMemory(options.serverPid, "VmHWM");
  SoakClient last(channel);
  report.last = tessera::soak::normalRequest(last, setup);

  const nlohmann::json json = toJson(options, report);
  if (!options.json.empty()) std::ofstream(options.json) << json.dump(2) << "\n";
  printMarkdown(json);
  return json["unexpected"].get<int>() == 0 && json["last_request_ok"].get<bool>() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Hostile and normal requests from many clients, the server's memory watched"};
  Options options;
  app.add_option("--server", options.server, "HOST:PORT of a running tessera-server")->required();
  app.add_option("--server-pid", options.serverPid, "Its process id, for its memory (/proc/PID/status)")->required();
  app.add_option("--models", options.models, "Folder with the models' OBJ files")->required();
  app.add_option("--small", options.small, "Model for normal requests")->capture_default_str();
  app.add_option("--large", options.large, "Model for hostile output requests")->capture_default_str();
  app.add_option("--clients", options.clients, "Clients, each on its own channel")->capture_default_str()->check(CLI::Range(1, 256));
  app.add_option("--hostile", options.hostile, "How many of them are hostile")->capture_default_str()->check(CLI::Range(0, 256));
  app.add_option("--cold", options.cold, "How many of them are the cold storm")
      ->capture_default_str()
      ->check(CLI::Range(0, 256));
  app.add_option("--cold-models", options.coldModels, "Models the cold storm copies")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--cold-tolerance", options.coldTolerance, "Relative tolerance of the cold storm's tessellations")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--seconds", options.seconds, "How long the clients run")->capture_default_str()->check(CLI::Range(1.0, 86400.0));
  app.add_option("--token", options.token, "The server's bearer token, if it has one");
  app.add_option("--seed", options.seed, "Seed of the clients' choices")->capture_default_str();
  app.add_option("--json", options.json, "Also write the results as JSON here");
  CLI11_PARSE(app, argc, argv);
  if (options.hostile + options.cold > options.clients) {
    std::fprintf(stderr, "--hostile %d and --cold %d are more than --clients %d\n", options.hostile, options.cold,
                 options.clients);
    return 2;
  }
  try {
    return run(options);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "tessera-soak: %s\n", error.what());
    return 2;
  }
}
