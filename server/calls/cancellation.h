// Cooperative cancellation for long work: the server hands a token to the code that loops (the
// tessellation engine, the admission queue) and that code polls it, because a gRPC deadline or a
// client hanging up cannot interrupt a computation any other way.
#pragma once

#include <functional>
#include <stdexcept>
#include <utility>

namespace tessera::server {

// Thrown by work that noticed its token fired; the server answers CANCELLED or
// DEADLINE_EXCEEDED, whichever applies.
class OperationCancelled : public std::runtime_error {
 public:
  OperationCancelled() : std::runtime_error("the call was cancelled") {}
};

class CancellationToken {
 public:
  // A token that never fires (for work outside a call).
  CancellationToken() = default;
  explicit CancellationToken(std::function<bool()> probe) : probe_(std::move(probe)) {}

  // Cheap enough to call once per ring or per patch batch; safe from several threads.
  bool cancelled() const { return probe_ && probe_(); }
  void throwIfCancelled() const {
    if (cancelled()) throw OperationCancelled();
  }

 private:
  std::function<bool()> probe_;
};

}  // namespace tessera::server
