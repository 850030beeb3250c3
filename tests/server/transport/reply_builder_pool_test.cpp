// ReplyBuilderPool: keeps `base` idle builders plus one per open connection, frees the rest as
// they are given back and a closing connection's share at once, frees a builder grown by a
// reply past kLargestKeptBytes, and hands out cleared builders.
#include "server/transport/reply_builder_pool.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace sweepd::server {
namespace {

// A builder grown by a reply of `bytes` bytes.
flatbuffers::FlatBufferBuilder grown(std::size_t bytes) {
  flatbuffers::FlatBufferBuilder builder(1024);
  const std::vector<std::uint8_t> payload(bytes, 7);
  builder.Finish(builder.CreateVector(payload));
  return builder;
}

TEST(ReplyBuilderPool, KeepsTheBasePlusOnePerOpenConnection) {
  ReplyBuilderPool pool(2);
  pool.set_connections(3);
  for (int i = 0; i < 7; ++i) pool.give_back(grown(1000));
  EXPECT_EQ(pool.idle(), 5u);  // 2 + 3; the other two were freed
}

TEST(ReplyBuilderPool, ClosingConnectionsFreeTheirShareAtOnce) {
  ReplyBuilderPool pool(2);
  pool.set_connections(4);
  for (int i = 0; i < 6; ++i) pool.give_back(grown(1000));
  ASSERT_EQ(pool.idle(), 6u);
  pool.set_connections(1);
  EXPECT_EQ(pool.idle(), 3u);
  pool.set_connections(0);
  EXPECT_EQ(pool.idle(), 2u);
  pool.give_back(grown(1000));
  EXPECT_EQ(pool.idle(), 2u);  // the base is full
}

// A builder that carried a position map or a sheet is not kept: idle, it would hold a frame's
// worth of memory outside the work budget (issue 49 item 2).
TEST(ReplyBuilderPool, ABuilderGrownPastTheLargestKeptReplyIsFreed) {
  ReplyBuilderPool pool(2);
  pool.give_back(grown(ReplyBuilderPool::kLargestKeptBytes + 1));
  EXPECT_EQ(pool.idle(), 0u);
  pool.give_back(grown(ReplyBuilderPool::kLargestKeptBytes - 64));  // with its vector's length
  EXPECT_EQ(pool.idle(), 1u);
}

TEST(ReplyBuilderPool, TakeHandsOutAClearedBuilderAndMakesOneWhenNoneIsIdle) {
  ReplyBuilderPool pool(1);
  pool.give_back(grown(100'000));
  ASSERT_EQ(pool.idle(), 1u);
  EXPECT_EQ(pool.take().GetSize(), 0u);  // the reply it held is gone
  EXPECT_EQ(pool.idle(), 0u);
  EXPECT_EQ(pool.take().GetSize(), 0u);  // none idle: a new one
}

}  // namespace
}  // namespace sweepd::server
