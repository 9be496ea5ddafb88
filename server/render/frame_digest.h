// The SHA-256 a frame header announces for its image, computed in slices that poll the call's
// cancellation: an 8192 x 8192 RAW frame is 256 MiB, ~0.6 s of hashing on the 2-core
// development box, which a deadline must not have to wait out (issue 47: every render stage
// ends within 1 s of the deadline).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "server/calls/cancellation.h"

namespace tessera::server {

// Lower-case hex, as core's sha256Hex; throws OperationCancelled when `cancel` fires.
std::string frameSha256Hex(std::span<const uint8_t> bytes, const CancellationToken& cancel);

}  // namespace tessera::server
