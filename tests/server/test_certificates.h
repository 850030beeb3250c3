// TestCertificates: a throwaway PKI for the TLS tests, made with the openssl command line in
// a directory of the test's own: a CA, a server certificate it signs for 127.0.0.1 and
// localhost (subjectAltName), a client certificate it signs (CN render-node), and a second,
// unrelated CA (other_ca) that signed none of them. EC P-256 keys; all files PEM.
//   TestCertificates::make(directory)  the files, or nullopt when openssl is not installed
//                                      (the caller skips, saying so); std::runtime_error with
//                                      openssl's messages when it fails
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>

namespace sweepd::test {

struct TestCertificates {
  std::filesystem::path ca, server_cert, server_key, client_cert, client_key, other_ca;

  static std::optional<TestCertificates> make(const std::filesystem::path& directory) {
    if (std::system("command -v openssl >/dev/null 2>&1") != 0) return std::nullopt;
    const std::string d = directory.string();
    std::ofstream(directory / "extensions.cnf")
        << "[server]\nsubjectAltName=IP:127.0.0.1,DNS:localhost\n"
           "[client]\nextendedKeyUsage=clientAuth\n";
    const std::string key = " -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes";
    const std::string sign = " -CA " + d + "/ca.pem -CAkey " + d + "/ca.key -CAcreateserial" +
                             " -days 2 -extfile " + d + "/extensions.cnf";
    const std::string script =
        "set -e; cd " + d + "; exec 2>openssl.log;" + " openssl req -x509" + key +
        " -keyout ca.key -out ca.pem -subj /CN=test-ca -days 2;" + " openssl req -x509" + key +
        " -keyout other_ca.key -out other_ca.pem -subj /CN=other-ca" + " -days 2;" +
        " openssl req" + key + " -keyout server.key -out server.csr -subj /CN=sweepd;" +
        " openssl x509 -req -in server.csr -out server.pem" + sign + " -extensions server;" +
        " openssl req" + key + " -keyout client.key -out client.csr -subj /CN=render-node;" +
        " openssl x509 -req -in client.csr -out client.pem" + sign + " -extensions client";
    if (std::system(("bash -c '" + script + "'").c_str()) != 0) {
      std::ifstream log(directory / "openssl.log");
      throw std::runtime_error("openssl failed: " +
                               std::string(std::istreambuf_iterator<char>(log), {}));
    }
    return TestCertificates{directory / "ca.pem",     directory / "server.pem",
                            directory / "server.key", directory / "client.pem",
                            directory / "client.key", directory / "other_ca.pem"};
  }
};

}  // namespace sweepd::test
