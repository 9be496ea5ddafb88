#include "server/calls/call_notes.h"

namespace tessera::server {

void CallNotes::note(const grpc::ServerContextBase* call, std::string key, std::string text) {
  std::lock_guard lock(mutex_);
  notes_[call].push_back({std::move(key), std::move(text)});
}

void CallNotes::note(const grpc::ServerContextBase* call, std::string key, int64_t number) {
  std::lock_guard lock(mutex_);
  notes_[call].push_back({std::move(key), std::to_string(number), LogField::Kind::kNumber});
}

CallNotes::Notes CallNotes::take(const grpc::ServerContextBase* call) {
  std::lock_guard lock(mutex_);
  const auto found = notes_.find(call);
  if (found == notes_.end()) return {};
  Notes notes = std::move(found->second);
  notes_.erase(found);
  return notes;
}

}  // namespace tessera::server
