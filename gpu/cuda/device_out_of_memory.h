// The one CUDA failure a caller can act on: the device ran out of memory (the server's CUDA
// engine then runs the job on the CPU). A TesseraError of kind kLimitExceeded, so that where
// nobody acts on it it still answers RESOURCE_EXHAUSTED with its message. Plain C++.
#pragma once

#include <string>

#include "core/base/error.h"

namespace tessera::cuda {

class DeviceOutOfMemory : public TesseraError {
 public:
  explicit DeviceOutOfMemory(const std::string& message) : TesseraError(ErrorKind::kLimitExceeded, message) {}
};

}  // namespace tessera::cuda
