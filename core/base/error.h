// The one error type core/ throws for bad input: its message names the problem and where it is,
// so that the CLI can print it and the server can turn it into a gRPC status unchanged.
#pragma once

#include <stdexcept>
#include <string>

namespace tessera {

enum class ErrorKind {
  kInvalidInput,   // malformed or inconsistent data (bad index, NaN, degenerate face, ...)
  kUnsupported,    // valid input that uses a feature Tessera refuses (Chaikin creases, ...)
  kLimitExceeded,  // valid input past a configured size or work budget
};

class TesseraError : public std::runtime_error {
 public:
  TesseraError(ErrorKind kind, const std::string& message)
      : std::runtime_error(message), kind_(kind) {}
  ErrorKind kind() const { return kind_; }

 private:
  ErrorKind kind_;
};

[[noreturn]] inline void throwInvalid(const std::string& message) {
  throw TesseraError(ErrorKind::kInvalidInput, message);
}
[[noreturn]] inline void throwUnsupported(const std::string& message) {
  throw TesseraError(ErrorKind::kUnsupported, message);
}
[[noreturn]] inline void throwLimit(const std::string& message) {
  throw TesseraError(ErrorKind::kLimitExceeded, message);
}

}  // namespace tessera
