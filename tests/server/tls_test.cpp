// TLS: with --tls-cert/--tls-key the server speaks only TLS; clients that trust its certificate
// get through, plaintext clients do not. The certificate is made here with the openssl tool.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {
namespace {

// A self-signed certificate for 127.0.0.1; false if the openssl tool is missing or fails.
bool makeCertificate(const std::filesystem::path& dir) {
  std::string command = "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 "
                        "-nodes -days 1 -subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1 "
                        "-keyout " + (dir / "key.pem").string() + " -out " +
                        (dir / "cert.pem").string() + " > /dev/null 2>&1";
  int status = std::system(command.c_str());
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

TEST(Tls, ClientsThatTrustTheCertificateConnectAndPlaintextClientsCannot) {
  TempDir dir;
  if (!makeCertificate(dir.path())) GTEST_SKIP() << "the openssl tool could not make a certificate";
  auto server = ServerProcess::start(
      dir.path(), {"--store", "sqlite:" + (dir.path() / "m.db").string(), "--tls-cert",
                   (dir.path() / "cert.pem").string(), "--tls-key", (dir.path() / "key.pem").string()});
  ASSERT_TRUE(server);

  auto secure = v1::ServerInfoService::NewStub(server->channel());
  grpc::ClientContext context;
  prepare(context);
  v1::ServerInfo info;
  ASSERT_TRUE(secure->GetServerInfo(&context, {}, &info).ok());
  EXPECT_TRUE(info.tls());

  auto plaintext = v1::ServerInfoService::NewStub(
      grpc::CreateChannel(server->address(), grpc::InsecureChannelCredentials()));
  grpc::ClientContext plainContext;
  prepare(plainContext, {}, 5);
  EXPECT_EQ(plaintext->GetServerInfo(&plainContext, {}, &info).error_code(),
            grpc::StatusCode::UNAVAILABLE);

  if (std::filesystem::exists(TESSERA_CLI_BINARY)) {
    std::string command = std::string("env -u TESSERA_TOKEN ") + TESSERA_CLI_BINARY + " --server " +
                          server->address() + " --ca-cert " + (dir.path() / "cert.pem").string() +
                          " info > " + (dir.path() / "cli.txt").string() + " 2>&1";
    int status = std::system(command.c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << readFile(dir.path() / "cli.txt");
    EXPECT_NE(readFile(dir.path() / "cli.txt").find("tls           yes"), std::string::npos);
  }
}

// A key that is not the certificate's stops the server at start, saying so (gRPC alone would
// only fail to listen).
TEST(Tls, AKeyThatIsNotTheCertificatesStopsTheServerSayingSo) {
  TempDir first, second;
  if (!makeCertificate(first.path()) || !makeCertificate(second.path())) GTEST_SKIP() << "no openssl tool";
  auto [code, output] = failedStart(first.path(), "--store sqlite:" + (first.path() / "m.db").string() +
                                                      " --tls-cert " + (first.path() / "cert.pem").string() +
                                                      " --tls-key " + (second.path() / "key.pem").string());
  EXPECT_EQ(code, 1);
  EXPECT_NE(output.find("--tls-key is not the key of the certificate in --tls-cert"), std::string::npos) << output;
}

}  // namespace
}  // namespace tessera::test
