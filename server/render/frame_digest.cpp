#include "server/render/frame_digest.h"

#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <memory>
#include <stdexcept>

namespace tessera::server {
namespace {

// Hashed between two polls: ~20 ms here.
constexpr size_t kSliceBytes = 16 << 20;

struct DigestDeleter {
  void operator()(EVP_MD_CTX* context) const { EVP_MD_CTX_free(context); }
};

void check(int result) {
  if (result != 1) throw std::runtime_error("SHA-256 computation failed");
}

}  // namespace

std::string frameSha256Hex(std::span<const uint8_t> bytes, const CancellationToken& cancel) {
  std::unique_ptr<EVP_MD_CTX, DigestDeleter> context(EVP_MD_CTX_new());
  if (!context) throw std::runtime_error("SHA-256 computation failed");
  check(EVP_DigestInit_ex(context.get(), EVP_sha256(), nullptr));
  for (size_t offset = 0; offset < bytes.size(); offset += kSliceBytes) {
    cancel.throwIfCancelled();
    check(EVP_DigestUpdate(context.get(), bytes.data() + offset,
                           std::min(kSliceBytes, bytes.size() - offset)));
  }
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  check(EVP_DigestFinal_ex(context.get(), digest.data(), &length));
  constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(2 * length);
  for (unsigned int i = 0; i < length; ++i) {
    hex += kHex[digest[i] >> 4];
    hex += kHex[digest[i] & 15];
  }
  return hex;
}

}  // namespace tessera::server
