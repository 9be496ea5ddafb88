// Engines for the server's own tests only (selected with the hidden --test-engine flag), so that
// admission, cancellation and result streaming can be tested before real tessellation exists
// and independently of it. They produce no geometry: "pattern" output is not a GLB.
#pragma once

#include <memory>
#include <string>

#include "server/tessellation/tessellation_engine.h"

namespace tessera::server {

// "block": holds its job (and admission slot) until the call is cancelled or its deadline
// passes. "pattern": returns kPatternBytes of patternByte(i) as the "GLB".
std::unique_ptr<TessellationEngine> makeTestEngine(const std::string& kind);

inline constexpr size_t kPatternBytes = 200'003;  // three full 64 KiB chunks and a partial one
inline uint8_t patternByte(size_t i) { return static_cast<uint8_t>((i * 131 + (i >> 8)) & 0xff); }

}  // namespace tessera::server
