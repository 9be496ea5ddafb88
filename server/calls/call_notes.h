// Facts a handler learns about its call (the mesh, the triangles and bytes it sent) for the one
// log line request_observer writes when the call ends: keyed by the call's context, added by the
// handler, taken once by the observer (which also drops them for calls that end without a
// status).
#pragma once

#include <grpcpp/server_context.h>

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "server/operations/log_format.h"

namespace tessera::server {

class CallNotes {
 public:
  using Notes = std::vector<LogField>;
  void note(const grpc::ServerContextBase* call, std::string key, std::string text);
  void note(const grpc::ServerContextBase* call, std::string key, int64_t number);
  Notes take(const grpc::ServerContextBase* call);

 private:
  std::mutex mutex_;
  std::map<const grpc::ServerContextBase*, Notes> notes_;
};

}  // namespace tessera::server
