// SHA-256 as lower-case hex, for mesh content and GLB checksums (OpenSSL does the hashing).
#pragma once

#include <string>
#include <string_view>

namespace tessera {

std::string sha256Hex(std::string_view bytes);

}  // namespace tessera
