// client::Connection with TLS to a server that accepts the TCP connection and never answers
// the handshake (a hung or misconfigured peer): the handshake gives up after
// ClientTls::handshake_timeout with ReceiveTimeout naming the handshake, instead of waiting for
// ever — render_frames' reconnect to another replica depends on it.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>

#include "client/connection.h"

namespace sweepd::client {
namespace {

TEST(TlsHandshakeTimeout, ASilentServerIsLeftAfterTheTimeout) {
  // A listener that never accepts: the kernel completes the TCP handshake (backlog), and
  // nothing ever answers the ClientHello.
  const int listener = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(listen(listener, 4), 0);
  socklen_t length = sizeof address;
  getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length);
  const std::string server = "127.0.0.1:" + std::to_string(ntohs(address.sin_port));

  ClientTls tls;
  tls.enabled = true;
  tls.handshake_timeout = std::chrono::milliseconds(300);
  const auto start = std::chrono::steady_clock::now();
  try {
    Connection connection(server, tls);
    ADD_FAILURE() << "the handshake with a silent server succeeded";
  } catch (const ReceiveTimeout& error) {
    EXPECT_NE(std::string(error.what()).find(server), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("300 ms"), std::string::npos) << error.what();
  }
  // At least the timeout; far below the 30 s default (no bound on a loaded machine's slowness
  // is asserted above the timeout itself beyond that).
  const auto waited = std::chrono::steady_clock::now() - start;
  EXPECT_GE(waited, std::chrono::milliseconds(300));
  EXPECT_LT(waited, std::chrono::seconds(20));
  close(listener);
}

}  // namespace
}  // namespace sweepd::client
