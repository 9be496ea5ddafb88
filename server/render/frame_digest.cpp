#include "server/render/frame_digest.h"

#include <string_view>

#include "core/base/sha256.h"

namespace tessera::server {

std::string frameSha256Hex(std::span<const uint8_t> bytes, const CancellationToken& cancel) {
  return sha256Hex(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                   [&cancel] { cancel.throwIfCancelled(); });
}

}  // namespace tessera::server
