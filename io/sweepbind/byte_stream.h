// ByteWriter / ByteReader: little-endian binary encoding for our own file formats
// (.sweepbind). The reader checks every read against the end of its buffer and throws
// io::LoadError naming the file, the offset and what was being read, so a truncated or corrupt
// file never reads out of bounds.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "io/files/load_error.h"

namespace sweepd::io {

static_assert(std::endian::native == std::endian::little,
              "the binary formats are little-endian; add byte swapping for this platform");

class ByteWriter {
 public:
  template <typename T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(&value);
    buffer_.insert(buffer_.end(), bytes, bytes + sizeof(T));
  }
  template <typename T>
  void put_array(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<std::uint64_t>(values.size());
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(values.data());
    buffer_.insert(buffer_.end(), bytes, bytes + values.size_bytes());
  }
  void put_string(const std::string& text) {
    put_array(std::span<const char>(text.data(), text.size()));
  }
  std::vector<std::uint8_t>& bytes() { return buffer_; }

 private:
  std::vector<std::uint8_t> buffer_;
};

class ByteReader {
 public:
  ByteReader(std::span<const std::uint8_t> bytes, std::filesystem::path file, std::size_t base = 0)
      : bytes_(bytes), file_(std::move(file)), base_(base) {}

  template <typename T>
  T get(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T), what);
    T value;
    std::memcpy(&value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }
  // An array written by put_array; refuses counts above max_count or beyond the buffer.
  template <typename T>
  std::vector<T> get_array(const char* what, std::uint64_t max_count) {
    const auto count = get<std::uint64_t>(what);
    if (count > max_count)
      fail(std::string(what) + ": count " + std::to_string(count) + " exceeds the limit " +
           std::to_string(max_count));
    need(count * sizeof(T), what);
    std::vector<T> values(count);
    if (count) std::memcpy(values.data(), bytes_.data() + offset_, count * sizeof(T));
    offset_ += count * sizeof(T);
    return values;
  }
  std::string get_string(const char* what, std::uint64_t max_length = 1 << 16) {
    const std::vector<char> chars = get_array<char>(what, max_length);
    return std::string(chars.begin(), chars.end());
  }
  std::size_t remaining() const { return bytes_.size() - offset_; }
  [[noreturn]] void fail(const std::string& reason) const {
    throw LoadError(file_, reason + " (at byte " + std::to_string(base_ + offset_) + ")");
  }

 private:
  void need(std::uint64_t size, const char* what) const {
    if (size > remaining())
      fail(std::string("truncated: ") + what + " needs " + std::to_string(size) + " bytes, only " +
           std::to_string(remaining()) + " left");
  }

  std::span<const std::uint8_t> bytes_;
  std::filesystem::path file_;
  std::size_t base_;
  std::size_t offset_ = 0;
};

// CRC-32 (IEEE 802.3, the zlib/PNG one) of bytes.
std::uint32_t crc32(std::span<const std::uint8_t> bytes);

}  // namespace sweepd::io
