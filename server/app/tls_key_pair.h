// The TLS certificate and key the server is given, checked before it listens: gRPC only reports
// "cannot listen" when they are unreadable or do not belong together.
#pragma once

#include <string>

namespace tessera::server {

// Throws std::runtime_error naming the flag and the problem: a certificate or key that is not
// PEM, or a key that is not the certificate's.
void checkTlsKeyPair(const std::string& certificatePem, const std::string& keyPem);

}  // namespace tessera::server
