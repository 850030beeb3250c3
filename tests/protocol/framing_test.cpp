// Tests for protocol/framing.h: length-prefixed frames and the incremental FrameReader's
// typed errors (the stream must stay usable after each one).
#include "protocol/framing.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "protocol/messages.h"

namespace sweepd::protocol {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes hello_frame(std::string_view client_name = "framing-test") {
  flatbuffers::FlatBufferBuilder builder;
  const auto frame = build_hello(builder, "token", client_name);
  return {frame.begin(), frame.end()};
}

Bytes length_prefix(std::uint32_t length) {
  return {static_cast<std::uint8_t>(length), static_cast<std::uint8_t>(length >> 8),
          static_cast<std::uint8_t>(length >> 16), static_cast<std::uint8_t>(length >> 24)};
}

// One event with a copy of its frame: an event's own span lasts only until the next read().
struct Seen {
  FrameEvent event;
  Bytes frame;
  const Message* message() const { return GetSizePrefixedMessage(frame.data()); }
};

// Feeds all of `bytes` at once and collects every event until the reader wants more.
std::vector<Seen> read_all(FrameReader& reader, const Bytes& bytes) {
  std::vector<Seen> seen;
  std::span<const std::uint8_t> input(bytes);
  for (FrameEvent event = reader.read(input); event.status != FrameStatus::kPending;
       event = reader.read(input)) {
    Bytes frame(event.frame.begin(), event.frame.end());
    seen.push_back({std::move(event), std::move(frame)});
  }
  EXPECT_TRUE(input.empty());
  return seen;
}

void expect_hello(const Seen& seen, std::string_view client_name) {
  ASSERT_EQ(seen.event.status, FrameStatus::kFrame) << seen.event.reason;
  ASSERT_EQ(seen.message()->body_type(), Body::Hello);
  EXPECT_EQ(seen.message()->body_as_Hello()->client_name()->string_view(), client_name);
}

TEST(Framing, FrameIsLittleEndianLengthThenIdentifiedFlatBuffer) {
  const Bytes frame = hello_frame();
  const std::uint32_t length = frame[0] | frame[1] << 8 | frame[2] << 16 | frame[3] << 24;
  EXPECT_EQ(length + kLengthPrefixBytes, frame.size());
  EXPECT_EQ(std::string(frame.begin() + 8, frame.begin() + 12), "SWPD");
}

TEST(Framing, SeveralFramesInOneReadComeOutInOrder) {
  Bytes stream = hello_frame("first");
  const Bytes second = hello_frame("second");
  stream.insert(stream.end(), second.begin(), second.end());
  FrameReader reader;
  const auto events = read_all(reader, stream);
  ASSERT_EQ(events.size(), 2u);
  expect_hello(events[0], "first");
  expect_hello(events[1], "second");
  EXPECT_FALSE(reader.mid_frame());
}

TEST(Framing, OversizedFrameIsRefusedBeforeAnyBodyByteOrAllocation) {
  FrameReader reader(1024);
  // A 1 GiB claim: refused from its 4 prefix bytes alone, nothing reserved for it.
  const Bytes prefix = length_prefix(1u << 30);
  std::span<const std::uint8_t> input(prefix);
  const FrameEvent event = reader.read(input);
  ASSERT_EQ(event.status, FrameStatus::kError);
  EXPECT_EQ(event.error, FrameError::kOversized);
  EXPECT_EQ(event.declared_bytes, 1u << 30);
  EXPECT_NE(event.reason.find("1073741824"), std::string::npos) << event.reason;
  EXPECT_NE(event.reason.find("1024"), std::string::npos) << event.reason;
  EXPECT_EQ(reader.storage_capacity_bytes(), 0u);
  EXPECT_TRUE(reader.mid_frame());
  EXPECT_EQ(error_code_for(event.error), ErrorCode::FrameTooLarge);
}

TEST(Framing, OversizedBodyIsSkippedThenTheNextFrameIsRead) {
  FrameReader reader(1024);
  Bytes stream = length_prefix(5000);
  stream.resize(stream.size() + 5000, 0xab);
  const Bytes next = hello_frame("after");
  stream.insert(stream.end(), next.begin(), next.end());
  // Split into 97-byte pieces so the skipped body spans many reads.
  std::vector<Seen> events;
  for (std::size_t at = 0; at < stream.size(); at += 97) {
    Bytes piece(stream.begin() + at, stream.begin() + std::min(stream.size(), at + 97));
    for (auto& event : read_all(reader, piece)) events.push_back(std::move(event));
  }
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].event.error, FrameError::kOversized);
  expect_hello(events[1], "after");
  // Only the accepted frame was ever stored (rounded up to 8-byte words).
  EXPECT_LT(reader.storage_capacity_bytes(), next.size() + 8);
}

TEST(Framing, WrongIdentifierIsATypedErrorNamingTheIdentifier) {
  flatbuffers::FlatBufferBuilder builder;
  builder.FinishSizePrefixed(
      CreateMessage(builder, 3, Body::ListModels, CreateListModels(builder).Union()), "ABCD");
  Bytes stream(builder.GetBufferPointer(), builder.GetBufferPointer() + builder.GetSize());
  const Bytes next = hello_frame("after");
  stream.insert(stream.end(), next.begin(), next.end());
  FrameReader reader;
  const auto events = read_all(reader, stream);
  ASSERT_EQ(events.size(), 2u);
  ASSERT_EQ(events[0].event.status, FrameStatus::kError);
  EXPECT_EQ(events[0].event.error, FrameError::kWrongIdentifier);
  EXPECT_NE(events[0].event.reason.find("\"ABCD\""), std::string::npos) << events[0].event.reason;
  EXPECT_EQ(error_code_for(events[0].event.error), ErrorCode::WrongIdentifier);
  expect_hello(events[1], "after");
}

TEST(Framing, TruncatedFrameStaysPendingUntilItsLastByte) {
  const Bytes frame = hello_frame("slow");
  FrameReader reader;
  // Two bytes of the prefix, then all but the last byte of the body: nothing yet.
  Bytes head(frame.begin(), frame.begin() + 2);
  EXPECT_TRUE(read_all(reader, head).empty());
  EXPECT_TRUE(reader.mid_frame());
  Bytes middle(frame.begin() + 2, frame.end() - 1);
  EXPECT_TRUE(read_all(reader, middle).empty());
  EXPECT_TRUE(reader.mid_frame());
  const auto events = read_all(reader, Bytes{frame.back()});
  ASSERT_EQ(events.size(), 1u);
  expect_hello(events[0], "slow");
  EXPECT_FALSE(reader.mid_frame());
}

TEST(Framing, ZeroLengthFrameIsTooShortAndTheStreamGoesOn) {
  Bytes stream = length_prefix(0);
  const Bytes next = hello_frame("after");
  stream.insert(stream.end(), next.begin(), next.end());
  FrameReader reader;
  const auto events = read_all(reader, stream);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].event.error, FrameError::kTooShort);
  EXPECT_EQ(events[0].event.declared_bytes, 0u);
  EXPECT_EQ(error_code_for(events[0].event.error), ErrorCode::BadFrame);
  expect_hello(events[1], "after");
}

TEST(Framing, BodyCutShortInsideItsLengthFailsVerification) {
  // A valid frame whose length prefix claims 8 bytes fewer: the offsets now point past
  // the end, which the verifier must catch (the cut-off tail is then read as a new frame).
  Bytes frame = hello_frame("cut");
  const std::uint32_t shorter = static_cast<std::uint32_t>(frame.size() - kLengthPrefixBytes - 8);
  const Bytes prefix = length_prefix(shorter);
  std::copy(prefix.begin(), prefix.end(), frame.begin());
  frame.resize(kLengthPrefixBytes + shorter);
  FrameReader reader;
  const auto events = read_all(reader, frame);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].event.error, FrameError::kVerificationFailed) << events[0].event.reason;
}

TEST(Framing, GarbageWithTheRightIdentifierFailsVerificationAndTheStreamGoesOn) {
  // 500 random bodies (random root offsets, vtables, lengths) carrying "SWPD": the reader
  // must type each as an error (or, vanishingly unlikely, a valid Message), never crash or
  // lose its place in the stream, which the closing Hello proves.
  std::mt19937 random(23);
  Bytes stream;
  for (int i = 0; i < 500; ++i) {
    const std::uint32_t length = 8 + random() % 200;
    const Bytes prefix = length_prefix(length);
    stream.insert(stream.end(), prefix.begin(), prefix.end());
    Bytes body(length);
    for (auto& byte : body) byte = static_cast<std::uint8_t>(random());
    std::copy_n("SWPD", 4, body.begin() + 4);
    stream.insert(stream.end(), body.begin(), body.end());
  }
  const Bytes next = hello_frame("after");
  stream.insert(stream.end(), next.begin(), next.end());
  FrameReader reader;
  const auto events = read_all(reader, stream);
  ASSERT_EQ(events.size(), 501u);
  int failed = 0;
  for (int i = 0; i < 500; ++i) {
    if (events[i].event.status == FrameStatus::kError) {
      EXPECT_EQ(events[i].event.error, FrameError::kVerificationFailed);
      ++failed;
    }
  }
  EXPECT_GE(failed, 490);
  expect_hello(events[500], "after");
}

TEST(Framing, ErrorNamesAreDistinct) {
  EXPECT_STREQ(frame_error_name(FrameError::kOversized), "oversized");
  EXPECT_STREQ(frame_error_name(FrameError::kWrongIdentifier), "wrong_identifier");
  EXPECT_STREQ(frame_error_name(FrameError::kVerificationFailed), "verification_failed");
  EXPECT_STREQ(frame_error_name(FrameError::kTooShort), "too_short");
}

}  // namespace
}  // namespace sweepd::protocol
