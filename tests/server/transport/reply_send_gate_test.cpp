// ReplySendGate: a worker sends only while the I/O thread holds nothing, a short send keeps the
// socket for the I/O thread's remainder, and after close() no worker sends. On a socketpair
// whose peer reads what was sent.
#include "server/transport/reply_send_gate.h"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <numeric>
#include <vector>

namespace sweepd::server {
namespace {

class ReplySendGateTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, sockets_), 0); }
  void TearDown() override {
    ::close(sockets_[0]);
    ::close(sockets_[1]);
  }
  std::vector<std::uint8_t> read_peer(std::size_t bytes) {
    std::vector<std::uint8_t> out(bytes);
    std::size_t got = 0;
    while (got < bytes) {
      const ssize_t n = ::read(sockets_[1], out.data() + got, bytes - got);
      if (n <= 0) break;
      got += static_cast<std::size_t>(n);
    }
    out.resize(got);
    return out;
  }

  int sockets_[2] = {-1, -1};
};

TEST_F(ReplySendGateTest, AWorkerSendsAWholeReplyWhenTheSocketIsFree) {
  ReplySendGate gate(sockets_[0]);
  std::vector<std::uint8_t> reply(1000);
  std::iota(reply.begin(), reply.end(), 0);
  EXPECT_EQ(gate.try_send(reply), std::optional<std::size_t>(1000));
  EXPECT_EQ(read_peer(1000), reply);
  EXPECT_TRUE(gate.acquire());  // nothing left over: the I/O thread may write next
}

TEST_F(ReplySendGateTest, AWorkerSendsNothingWhileTheIoThreadHoldsTheSocket) {
  ReplySendGate gate(sockets_[0]);
  ASSERT_TRUE(gate.acquire());
  const std::vector<std::uint8_t> reply(100, 1);
  EXPECT_EQ(gate.try_send(reply), std::nullopt);
  gate.release();
  EXPECT_EQ(gate.try_send(reply), std::optional<std::size_t>(100));
}

TEST_F(ReplySendGateTest, AShortSendKeepsTheSocketForItsRemainder) {
  const int small = 4096;
  ASSERT_EQ(::setsockopt(sockets_[0], SOL_SOCKET, SO_SNDBUF, &small, sizeof small), 0);
  ReplySendGate gate(sockets_[0]);
  const std::vector<std::uint8_t> reply(4 << 20, 2);  // far more than the socket takes unread
  const std::optional<std::size_t> sent = gate.try_send(reply);
  ASSERT_TRUE(sent.has_value());
  EXPECT_LT(*sent, reply.size());
  EXPECT_FALSE(gate.acquire());  // another reply must not cut into this one
  EXPECT_EQ(gate.try_send(reply), std::nullopt);
  gate.take_remainder();
  EXPECT_TRUE(gate.acquire());
}

TEST_F(ReplySendGateTest, NoSendAfterClose) {
  ReplySendGate gate(sockets_[0]);
  gate.close();
  EXPECT_EQ(gate.try_send(std::vector<std::uint8_t>(10, 3)), std::nullopt);
}

TEST_F(ReplySendGateTest, TlsAndWebSocketStreamsNeverSendFromAWorker) {
  ReplySendGate gate(-1);
  EXPECT_EQ(gate.try_send(std::vector<std::uint8_t>(10, 3)), std::nullopt);
}

}  // namespace
}  // namespace sweepd::server
