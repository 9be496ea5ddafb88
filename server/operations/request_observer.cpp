#include "server/operations/request_observer.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <optional>
#include <random>
#include <string>
#include <unordered_set>

#include <google/protobuf/descriptor.h>

#include "tessera/status_names.h"

namespace tessera::server {
namespace {

using grpc::experimental::InterceptionHookPoints;

constexpr const char* kRequestIdKey = "x-request-id";
constexpr size_t kMaxRequestIdLength = 64;

bool isSaneRequestId(std::string_view id) {
  if (id.empty() || id.size() > kMaxRequestIdLength) return false;
  for (char c : id) {
    if (c <= 0x20 || c >= 0x7f) return false;
  }
  return true;
}

// Process-unique and unlikely to collide across replicas: a random prefix per process and a
// counter.
std::string newRequestId() {
  static const uint32_t prefix = std::random_device{}();
  static std::atomic<uint64_t> counter{0};
  return fmt::format("{:08x}-{:x}", prefix, ++counter);
}

// The methods this server serves, as gRPC names them ("/package.Service/Method"): Tessera's
// services from the generated descriptors, health and reflection by name.
const std::unordered_set<std::string>& servedMethods() {
  static const std::unordered_set<std::string> methods = [] {
    std::unordered_set<std::string> names = {"/grpc.health.v1.Health/Check", "/grpc.health.v1.Health/Watch",
                                             "/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo",
                                             "/grpc.reflection.v1.ServerReflection/ServerReflectionInfo"};
    for (const char* service : {"MeshService", "TessellationService", "RenderService", "ServerInfoService"}) {
      const auto* descriptor =
          google::protobuf::DescriptorPool::generated_pool()->FindServiceByName(std::string("tessera.v1.") + service);
      for (int m = 0; descriptor && m < descriptor->method_count(); ++m) {
        names.insert("/" + descriptor->full_name() + "/" + descriptor->method(m)->name());
      }
    }
    return names;
  }();
  return methods;
}

// Metrics label a call by its method only when the server serves it: names a client makes up
// share one label, so the metrics stay bounded whatever clients send.
std::string methodLabel(const char* method) {
  return method && servedMethods().count(method) ? std::string(method) : std::string("unknown");
}

class RequestObserver final : public grpc::experimental::Interceptor {
 public:
  RequestObserver(grpc::experimental::ServerRpcInfo* info, ServerMetrics& metrics, LogFormat format)
      : info_(info), metrics_(metrics), format_(format), start_(std::chrono::steady_clock::now()) {}

  ~RequestObserver() override {
    if (!finished_) finish();
  }

  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::POST_RECV_INITIAL_METADATA)) {
      readRequestId(*methods->GetRecvInitialMetadata());
      if (auto* context = info_->server_context()) peer_ = context->peer();
    }
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_INITIAL_METADATA)) {
      methods->GetSendInitialMetadata()->emplace(kRequestIdKey, requestId());
    }
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_STATUS)) {
      grpc::Status status = methods->GetSendStatus();
      // gRPC answers a request it could not parse with INTERNAL and no message, before any
      // handler runs (every handler names its errors): say what it was.
      if (status.error_code() == grpc::StatusCode::INTERNAL && status.error_message().empty()) {
        status = grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                              fmt::format("{}: the request is not a valid message for this method (a broken "
                                          "protobuf, or a string field that is not UTF-8)",
                                          methodLabel(info_->method())));
        methods->ModifySendStatus(status);
      }
      code_ = status.error_code();
      message_ = status.error_message();
      abandonedByClient();
      // Counted before the status leaves, so that a client that has its answer can already
      // see it in the metrics (the interceptor itself may live on a little after the call).
      finish();
    }
    methods->Proceed();
  }

 private:
  void readRequestId(const std::multimap<grpc::string_ref, grpc::string_ref>& metadata) {
    auto it = metadata.find(kRequestIdKey);
    if (it == metadata.end()) return;
    std::string_view id(it->second.data(), it->second.size());
    if (isSaneRequestId(id)) requestId_ = std::string(id);
  }

  // A call the client gave up on (its deadline passed, or it cancelled) never delivers the
  // status its handler sends (the default health service's Watch sends UNKNOWN): counted as
  // what the client saw. A handler that finished its work with OK all the same stays OK.
  void abandonedByClient() {
    const grpc::ServerContextBase* context = info_->server_context();
    if (context == nullptr || !context->IsCancelled() || code_ == grpc::StatusCode::OK) return;
    const bool late = context->deadline() <= std::chrono::system_clock::now();
    code_ = late ? grpc::StatusCode::DEADLINE_EXCEEDED : grpc::StatusCode::CANCELLED;
  }

  const std::string& requestId() {
    if (requestId_.empty()) requestId_ = newRequestId();
    return requestId_;
  }

  // Counts, times and logs the call once: when its status is sent, or, for a call whose status
  // was never sent (the client went away first), as CANCELLED when the interceptor is destroyed.
  void finish() {
    finished_ = true;
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::string method = methodLabel(info_->method());
    grpc::StatusCode code = code_.value_or(grpc::StatusCode::CANCELLED);
    std::string codeName(statusCodeName(code));
    metrics_.requests.add({method, codeName});
    metrics_.latency.observe({method}, seconds);
    bool isHealth = method.rfind("/grpc.health.v1.", 0) == 0;
    auto level = isHealth ? spdlog::level::debug
                 : code == grpc::StatusCode::INTERNAL || code == grpc::StatusCode::DATA_LOSS
                     ? spdlog::level::err
                     : spdlog::level::info;
    std::vector<LogField> fields = {{"request_id", requestId()},
                                    {"method", method},
                                    {"status", codeName},
                                    {"duration_ms", fmt::format("{:.2f}", seconds * 1e3), LogField::Kind::kNumber},
                                    {"peer", peer_}};
    if (!message_.empty()) fields.push_back({"message", message_, LogField::Kind::kQuoted});
    for (LogField& note : metrics_.notes.take(info_->server_context())) fields.push_back(std::move(note));
    spdlog::log(level, "{}", structuredPayload(format_, fields));
  }

  grpc::experimental::ServerRpcInfo* info_;
  ServerMetrics& metrics_;
  const LogFormat format_;
  std::chrono::steady_clock::time_point start_;
  std::string requestId_;
  std::string peer_ = "unknown";
  std::optional<grpc::StatusCode> code_;
  std::string message_;
  bool finished_ = false;
};

}  // namespace

grpc::experimental::Interceptor* RequestObserverFactory::CreateServerInterceptor(
    grpc::experimental::ServerRpcInfo* info) {
  return new RequestObserver(info, metrics_, format_);
}

}  // namespace tessera::server
