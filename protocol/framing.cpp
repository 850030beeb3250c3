#include "protocol/framing.h"

#include <algorithm>
#include <cstring>

namespace sweepd::protocol {
namespace {

// The identifier as readable text: printable ASCII as is, other bytes as \xNN.
std::string printable_identifier(const std::uint8_t* bytes) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string text;
  for (std::size_t i = 0; i < flatbuffers::kFileIdentifierLength; ++i) {
    const std::uint8_t byte = bytes[i];
    if (byte >= 0x20 && byte < 0x7f && byte != '\\' && byte != '"') {
      text += static_cast<char>(byte);
    } else {
      text += "\\x";
      text += kHex[byte >> 4];
      text += kHex[byte & 0xf];
    }
  }
  return text;
}

FrameEvent error_event(FrameError error, std::uint32_t declared_bytes, std::string reason) {
  FrameEvent event;
  event.status = FrameStatus::kError;
  event.error = error;
  event.declared_bytes = declared_bytes;
  event.reason = std::move(reason);
  return event;
}

}  // namespace

std::span<const std::uint8_t> finish_frame(flatbuffers::FlatBufferBuilder& builder,
                                           flatbuffers::Offset<Message> message) {
  builder.FinishSizePrefixed(message, kFileIdentifier);
  return {builder.GetBufferPointer(), builder.GetSize()};
}

const char* frame_error_name(FrameError error) {
  switch (error) {
    case FrameError::kNone:
      return "none";
    case FrameError::kTooShort:
      return "too_short";
    case FrameError::kOversized:
      return "oversized";
    case FrameError::kWrongIdentifier:
      return "wrong_identifier";
    case FrameError::kVerificationFailed:
      return "verification_failed";
    case FrameError::kOverBudget:
      return "over_budget";
  }
  return "unknown";
}

ErrorCode error_code_for(FrameError error) {
  switch (error) {
    case FrameError::kOversized:
      return ErrorCode::FrameTooLarge;
    case FrameError::kWrongIdentifier:
      return ErrorCode::WrongIdentifier;
    case FrameError::kOverBudget:
      return ErrorCode::ResourceExhausted;
    case FrameError::kTooShort:
    case FrameError::kVerificationFailed:
      return ErrorCode::BadFrame;
    case FrameError::kNone:
      break;
  }
  return ErrorCode::Internal;
}

FrameReader::FrameReader(std::uint32_t max_frame_bytes, BufferBudget* budget)
    : max_frame_bytes_(max_frame_bytes), budget_(budget) {}

FrameReader::~FrameReader() { release_storage(); }

void FrameReader::release_storage() {
  if (budget_ != nullptr) budget_->give_back(storage_capacity_bytes());
  std::vector<Word>().swap(storage_);
}

bool FrameReader::make_room(std::size_t bytes) {
  const std::size_t words = (bytes + sizeof(Word) - 1) / sizeof(Word);
  if (words > storage_.capacity()) {
    const std::size_t frame_words =
        (kLengthPrefixBytes + body_bytes_ + sizeof(Word) - 1) / sizeof(Word);
    const std::size_t target = std::min(
        frame_words, std::max({words, 2 * storage_.capacity(), kKeptStorageBytes / sizeof(Word)}));
    if (budget_ != nullptr && !budget_->take((target - storage_.capacity()) * sizeof(Word)))
      return false;
    std::vector<Word> grown;
    grown.reserve(target);
    grown.assign(storage_.begin(), storage_.end());
    storage_.swap(grown);
    // reserve(n) allocates exactly n words in libstdc++; charge any excess all the same.
    if (budget_ != nullptr && storage_.capacity() > target)
      budget_->take_anyway((storage_.capacity() - target) * sizeof(Word));
  }
  if (storage_.size() < words) storage_.resize(words);
  return true;
}

FrameEvent FrameReader::refuse_over_budget() {
  const std::size_t stored = body_filled_;
  release_storage();
  skip_remaining_ = body_bytes_ - body_filled_;
  state_ = skip_remaining_ > 0 ? State::kSkipping : State::kLength;
  return error_event(FrameError::kOverBudget, body_bytes_,
                     "frame of " + std::to_string(body_bytes_) + " bytes refused after " +
                         std::to_string(stored) +
                         ": the server's buffer memory for all connections is in use; "
                         "send it again later");
}

bool FrameReader::mid_frame() const { return state_ != State::kLength || length_filled_ > 0; }

FrameEvent FrameReader::read(std::span<const std::uint8_t>& input) {
  while (!input.empty()) {
    switch (state_) {
      case State::kSkipping: {
        const std::size_t taken = std::min(input.size(), skip_remaining_);
        input = input.subspan(taken);
        skip_remaining_ -= taken;
        if (skip_remaining_ == 0) state_ = State::kLength;
        break;
      }
      case State::kLength: {
        const std::size_t taken = std::min(input.size(), kLengthPrefixBytes - length_filled_);
        std::memcpy(length_bytes_ + length_filled_, input.data(), taken);
        input = input.subspan(taken);
        length_filled_ += taken;
        if (length_filled_ == kLengthPrefixBytes) {
          FrameEvent event = start_body();
          if (event.status != FrameStatus::kPending) return event;
        }
        break;
      }
      case State::kBody: {
        const std::size_t taken = std::min(input.size(), body_bytes_ - body_filled_);
        if (!make_room(kLengthPrefixBytes + body_filled_ + taken)) return refuse_over_budget();
        std::memcpy(storage_bytes() + kLengthPrefixBytes + body_filled_, input.data(), taken);
        input = input.subspan(taken);
        body_filled_ += taken;
        if (body_filled_ == body_bytes_) return check_frame();
        break;
      }
    }
  }
  return {};
}

FrameEvent FrameReader::start_body() {
  length_filled_ = 0;
  body_bytes_ = flatbuffers::ReadScalar<std::uint32_t>(length_bytes_);  // little-endian
  if (body_bytes_ > max_frame_bytes_) {
    skip_remaining_ = body_bytes_;
    state_ = State::kSkipping;
    return error_event(FrameError::kOversized, body_bytes_,
                       "frame of " + std::to_string(body_bytes_) + " bytes exceeds the limit of " +
                           std::to_string(max_frame_bytes_) + " bytes");
  }
  // A large frame's storage is not kept for the small ones that follow.
  if (storage_capacity_bytes() > kKeptStorageBytes) release_storage();
  body_filled_ = 0;
  if (!make_room(kLengthPrefixBytes)) return refuse_over_budget();
  std::memcpy(storage_bytes(), length_bytes_, kLengthPrefixBytes);
  state_ = State::kBody;
  if (body_bytes_ == 0) return check_frame();
  return {};
}

FrameEvent FrameReader::check_frame() {
  state_ = State::kLength;
  const std::uint8_t* frame = storage_bytes();
  const std::size_t frame_bytes = kLengthPrefixBytes + body_bytes_;
  if (body_bytes_ < kMinimumFrameBytes) {
    return error_event(FrameError::kTooShort, body_bytes_,
                       "frame of " + std::to_string(body_bytes_) +
                           " bytes is too short for a FlatBuffer (at least " +
                           std::to_string(kMinimumFrameBytes) +
                           " bytes: root offset and file identifier)");
  }
  if (!SizePrefixedMessageBufferHasIdentifier(frame)) {
    return error_event(
        FrameError::kWrongIdentifier, body_bytes_,
        "frame identifier is \"" +
            printable_identifier(frame + kLengthPrefixBytes + sizeof(flatbuffers::uoffset_t)) +
            "\", expected \"" + kFileIdentifier + "\"");
  }
  flatbuffers::Verifier verifier(frame, frame_bytes);
  if (!VerifySizePrefixedMessageBuffer(verifier)) {
    return error_event(FrameError::kVerificationFailed, body_bytes_,
                       "frame of " + std::to_string(body_bytes_) +
                           " bytes is not a valid sweepd Message (FlatBuffers verification "
                           "failed)");
  }
  const Message* message = GetSizePrefixedMessage(frame);
  // The verifier accepts a union whose type is set and whose value is absent; no reader of a
  // body should have to check for that.
  if (message->body_type() != Body::NONE && message->body() == nullptr) {
    return error_event(FrameError::kVerificationFailed, body_bytes_,
                       std::string("frame says its body is a ") +
                           EnumNameBody(message->body_type()) + " but carries none");
  }
  FrameEvent event;
  event.status = FrameStatus::kFrame;
  event.declared_bytes = body_bytes_;
  event.frame = {frame, frame_bytes};
  event.message = message;
  return event;
}

}  // namespace sweepd::protocol
