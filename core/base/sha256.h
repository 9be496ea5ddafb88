// SHA-256 as lower-case hex, for mesh content and GLB checksums (OpenSSL does the hashing).
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace tessera {

// `betweenSlices`, when given, is called before each 16 MiB of the bytes and may throw: how a
// caller with a deadline stops hashing a large frame.
std::string sha256Hex(std::string_view bytes, const std::function<void()>& betweenSlices = {});

}  // namespace tessera
