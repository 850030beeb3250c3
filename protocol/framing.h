// Framing: how sweepd messages travel on a byte stream (TCP or Unix socket).
//
// A frame is a u32 little-endian length L, then L bytes holding one FlatBuffer whose root is
// protocol::Message and whose file identifier (bytes 4..8 of the body) is "SWPD". This is
// exactly FlatBuffers' size-prefixed layout (FinishSizePrefixed in every FlatBuffers
// language), whose alignment counts from the first byte of the length prefix.
//
// finish_frame finishes a builder as one frame, ready to send as it lies in the builder.
//
// FrameReader takes bytes as they arrive, split anywhere, and yields one event at a time:
//   kFrame:   a whole frame, identifier checked and verified as a Message;
//   kError:   a typed FrameError with a readable reason; the reader carries on with the
//             frames that follow, so the server can answer with an Error and keep serving;
//   kPending: every input byte was consumed and no frame is complete yet.
// A length over max_frame_bytes is refused as soon as its 4 bytes are in, before any body
// byte is read or any memory reserved; the reader then discards that many bytes as they
// arrive (never storing them). The frame storage grows as the body arrives (doubling, never
// past the frame), not when the length is read, so a peer that declares a large frame and
// trickles it holds only what it has sent; it holds at most 4 + max_frame_bytes bytes, is
// reused for frames up to kKeptStorageBytes and released before the next frame after a larger
// one. With a BufferBudget, the reader takes its storage from the budget before it grows and
// gives it back when it is released; a frame the budget cannot hold is refused (kOverBudget)
// and the rest of its body discarded.
// set_max_frame_bytes(n) applies to frames whose length is read after the call (sweepd allows
// only a small frame before Hello).
//
//   FrameReader reader(max_frame_bytes);
//   std::span<const std::uint8_t> input(received, received_count);
//   for (FrameEvent event = reader.read(input); event.status != FrameStatus::kPending;
//        event = reader.read(input)) { ... event.message ... }
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "protocol/buffer_budget.h"
#include "protocol/sweepd_generated.h"

namespace sweepd::protocol {

inline constexpr char kFileIdentifier[] = "SWPD";
inline constexpr std::size_t kLengthPrefixBytes = 4;
// The smallest FlatBuffer body: root offset (4 bytes) and file identifier (4 bytes).
inline constexpr std::size_t kMinimumFrameBytes = 8;
inline constexpr std::uint32_t kDefaultMaxFrameBytes = 64u << 20;  // 64 MiB

// Finishes `builder` with `message` as its root, size-prefixed and identified as "SWPD".
// Returns the whole frame (length prefix included), valid until the builder changes.
std::span<const std::uint8_t> finish_frame(flatbuffers::FlatBufferBuilder& builder,
                                           flatbuffers::Offset<Message> message);

enum class FrameStatus { kPending, kFrame, kError };

enum class FrameError {
  kNone,
  kTooShort,            // L < kMinimumFrameBytes (including a zero-length frame)
  kOversized,           // L > max_frame_bytes; the body is skipped, never stored
  kWrongIdentifier,     // bytes 4..8 of the body are not "SWPD"
  kVerificationFailed,  // not a valid Message FlatBuffer (garbage, truncated offsets, ...)
  kOverBudget,          // the reader's BufferBudget could not hold the frame; body discarded
};

// A short name for logs: "too_short", "oversized", ...
const char* frame_error_name(FrameError error);
// The protocol's Error code to answer a frame error with.
ErrorCode error_code_for(FrameError error);

struct FrameEvent {
  FrameStatus status = FrameStatus::kPending;
  FrameError error = FrameError::kNone;
  std::string reason;                   // kError: what was wrong, with sizes or identifier
  std::uint32_t declared_bytes = 0;     // L from the length prefix (kFrame and kError)
  std::span<const std::uint8_t> frame;  // kFrame: prefix and body; valid until next read()
  const Message* message = nullptr;     // kFrame: the verified root, points into `frame`
};

class FrameReader {
 public:
  // Storage up to this size is kept between frames (a pose is about 1 KiB).
  static constexpr std::size_t kKeptStorageBytes = 64 * 1024;

  explicit FrameReader(std::uint32_t max_frame_bytes = kDefaultMaxFrameBytes,
                       BufferBudget* budget = nullptr);
  ~FrameReader();
  FrameReader(const FrameReader&) = delete;
  FrameReader& operator=(const FrameReader&) = delete;

  void set_max_frame_bytes(std::uint32_t max_frame_bytes) { max_frame_bytes_ = max_frame_bytes; }

  // Consumes bytes from the front of `input` (shrinking it) up to the end of the next
  // frame or error. kPending means `input` is now empty.
  FrameEvent read(std::span<const std::uint8_t>& input);

  // True while part of a frame (or of a skipped oversized body) has been read: at the end
  // of the stream this means the last frame was truncated.
  bool mid_frame() const;
  // Bytes of memory the reader holds for frame storage (what it has taken from its budget).
  std::size_t storage_capacity_bytes() const { return storage_.capacity() * sizeof(Word); }
  std::uint32_t max_frame_bytes() const { return max_frame_bytes_; }

 private:
  using Word = std::uint64_t;  // 8-byte aligned storage: FlatBuffers' largest scalar
  enum class State { kLength, kBody, kSkipping };

  FrameEvent start_body();
  FrameEvent check_frame();
  // Makes room for `bytes` of prefix and body (growing by doubling, capped at the frame);
  // false when the budget cannot hold it.
  bool make_room(std::size_t bytes);
  void release_storage();
  FrameEvent refuse_over_budget();
  std::uint8_t* storage_bytes() { return reinterpret_cast<std::uint8_t*>(storage_.data()); }

  std::uint32_t max_frame_bytes_;
  BufferBudget* budget_;
  State state_ = State::kLength;
  std::uint8_t length_bytes_[kLengthPrefixBytes] = {};
  std::size_t length_filled_ = 0;
  std::uint32_t body_bytes_ = 0;    // L of the frame being read
  std::size_t body_filled_ = 0;     // body bytes stored so far
  std::size_t skip_remaining_ = 0;  // kSkipping: body bytes still to discard
  std::vector<Word> storage_;       // prefix + body of the current frame
};

}  // namespace sweepd::protocol
