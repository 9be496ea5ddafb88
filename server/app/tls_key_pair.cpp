#include "server/app/tls_key_pair.h"

#include <openssl/bio.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <memory>
#include <stdexcept>

namespace tessera::server {

namespace {

std::unique_ptr<BIO, decltype(&BIO_free)> memoryBio(const std::string& pem) {
  return {BIO_new_mem_buf(pem.data(), int(pem.size())), &BIO_free};
}

}  // namespace

void checkTlsKeyPair(const std::string& certificatePem, const std::string& keyPem) {
  auto certificateBio = memoryBio(certificatePem), keyBio = memoryBio(keyPem);
  std::unique_ptr<X509, decltype(&X509_free)> certificate(
      certificateBio ? PEM_read_bio_X509(certificateBio.get(), nullptr, nullptr, nullptr) : nullptr, &X509_free);
  if (!certificate) throw std::runtime_error("--tls-cert: not a PEM certificate");
  std::unique_ptr<EVP_PKEY, decltype(&EVP_PKEY_free)> key(
      keyBio ? PEM_read_bio_PrivateKey(keyBio.get(), nullptr, nullptr, nullptr) : nullptr, &EVP_PKEY_free);
  if (!key) throw std::runtime_error("--tls-key: not a PEM private key (or one that needs a passphrase)");
  if (X509_check_private_key(certificate.get(), key.get()) != 1) {
    throw std::runtime_error("--tls-key is not the key of the certificate in --tls-cert");
  }
}

}  // namespace tessera::server
