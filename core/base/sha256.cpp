#include "core/base/sha256.h"

#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <memory>
#include <stdexcept>

namespace tessera {

namespace {

// Hashed between two calls of `betweenSlices`: ~20 ms on the 2-core development VM.
constexpr size_t kSliceBytes = 16 << 20;

struct DigestDeleter {
  void operator()(EVP_MD_CTX* context) const { EVP_MD_CTX_free(context); }
};

void check(int result) {
  if (result != 1) throw std::runtime_error("SHA-256 computation failed");
}

}  // namespace

std::string sha256Hex(std::string_view bytes, const std::function<void()>& betweenSlices) {
  std::unique_ptr<EVP_MD_CTX, DigestDeleter> context(EVP_MD_CTX_new());
  if (!context) throw std::runtime_error("SHA-256 computation failed");
  check(EVP_DigestInit_ex(context.get(), EVP_sha256(), nullptr));
  for (size_t offset = 0; offset < bytes.size(); offset += kSliceBytes) {
    if (betweenSlices) betweenSlices();
    check(EVP_DigestUpdate(context.get(), bytes.data() + offset, std::min(kSliceBytes, bytes.size() - offset)));
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

}  // namespace tessera
