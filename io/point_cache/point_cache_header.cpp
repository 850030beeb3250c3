#include "io/point_cache/point_cache_header.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>

#include "io/files/load_error.h"

namespace sweepd::io {

namespace {

constexpr char kPc2Signature[12] = "POINTCACHE2";  // 11 letters and the terminating zero
constexpr std::uint64_t kPc2HeaderSize = 32;

bool little_endian(PointCacheFormat format) { return format == PointCacheFormat::kPc2; }

// A 32-bit value's bytes in the format's order, whatever the host's: PC2 is little-endian,
// MDD big-endian.
void put_u32(std::vector<std::uint8_t>& out, std::uint32_t bits, PointCacheFormat format) {
  for (int i = 0; i < 4; ++i) {
    const int shift = little_endian(format) ? 8 * i : 8 * (3 - i);
    out.push_back(static_cast<std::uint8_t>(bits >> shift));
  }
}

std::uint32_t get_u32(const std::uint8_t* bytes, PointCacheFormat format) {
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i) {
    const int shift = little_endian(format) ? 8 * i : 8 * (3 - i);
    value |= std::uint32_t{bytes[i]} << shift;
  }
  return value;
}

}  // namespace

std::optional<PointCacheFormat> point_cache_format(const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".pc2") return PointCacheFormat::kPc2;
  if (extension == ".mdd") return PointCacheFormat::kMdd;
  return std::nullopt;
}

std::uint64_t PointCacheHeader::header_size() const {
  if (format == PointCacheFormat::kPc2) return kPc2HeaderSize;
  return 8 + 4 * std::uint64_t(frame_count);
}

std::vector<std::uint8_t> point_cache_header_bytes(const PointCacheHeader& header) {
  std::vector<std::uint8_t> bytes;
  const PointCacheFormat format = header.format;
  if (format == PointCacheFormat::kPc2) {
    bytes.assign(kPc2Signature, kPc2Signature + sizeof kPc2Signature);
    put_u32(bytes, 1, format);  // file version
    put_u32(bytes, static_cast<std::uint32_t>(header.point_count), format);
    put_u32(bytes, std::bit_cast<std::uint32_t>(header.start_frame), format);
    put_u32(bytes, std::bit_cast<std::uint32_t>(header.sampling), format);
    put_u32(bytes, static_cast<std::uint32_t>(header.frame_count), format);
    return bytes;
  }
  put_u32(bytes, static_cast<std::uint32_t>(header.frame_count), format);
  put_u32(bytes, static_cast<std::uint32_t>(header.point_count), format);
  for (float time : header.times) put_u32(bytes, std::bit_cast<std::uint32_t>(time), format);
  return bytes;
}

PointCacheHeader read_point_cache_header(const std::filesystem::path& file) {
  const std::optional<PointCacheFormat> format = point_cache_format(file);
  if (!format) throw LoadError(file, "not a point cache: the name must end in .pc2 or .mdd");
  std::error_code size_error;
  const std::uint64_t size = std::filesystem::file_size(file, size_error);
  std::ifstream in(file, std::ios::binary);
  if (size_error || !in) throw LoadError(file, "cannot be read");
  PointCacheHeader header;
  header.format = *format;
  std::array<std::uint8_t, kPc2HeaderSize> fixed{};
  const std::uint64_t fixed_size = *format == PointCacheFormat::kPc2 ? kPc2HeaderSize : 8;
  if (size < fixed_size || !in.read(reinterpret_cast<char*>(fixed.data()), fixed_size))
    throw LoadError(file, std::to_string(size) + " bytes: shorter than a " +
                              (*format == PointCacheFormat::kPc2 ? "PC2" : "MDD") + " header");
  auto field = [&](std::size_t offset) { return get_u32(fixed.data() + offset, *format); };
  if (*format == PointCacheFormat::kPc2) {
    if (std::memcmp(fixed.data(), kPc2Signature, sizeof kPc2Signature) != 0)
      throw LoadError(file, "not a PC2 file: it does not start with POINTCACHE2");
    if (field(12) != 1)
      throw LoadError(file, "PC2 version " + std::to_string(field(12)) + ", only 1 is known");
    header.point_count = static_cast<std::int32_t>(field(16));
    header.start_frame = std::bit_cast<float>(field(20));
    header.sampling = std::bit_cast<float>(field(24));
    header.frame_count = static_cast<std::int32_t>(field(28));
  } else {
    header.frame_count = static_cast<std::int32_t>(field(0));
    header.point_count = static_cast<std::int32_t>(field(4));
  }
  if (header.point_count <= 0 || header.frame_count <= 0)
    throw LoadError(file, "the header promises " + std::to_string(header.frame_count) +
                              " frames of " + std::to_string(header.point_count) +
                              " points: a cache holds at least one of each");
  if (size != header.file_size())
    throw LoadError(file, std::to_string(size) + " bytes where its header promises " +
                              std::to_string(header.file_size()) + " (" +
                              std::to_string(header.frame_count) + " frames of " +
                              std::to_string(header.point_count) + " points): " +
                              (size < header.file_size() ? "truncated" : "bytes past its frames"));
  if (*format == PointCacheFormat::kMdd) {
    std::vector<std::uint8_t> times(4 * std::size_t(header.frame_count));
    if (!in.read(reinterpret_cast<char*>(times.data()), std::streamsize(times.size())))
      throw LoadError(file, "cannot read the frame times");
    for (std::size_t i = 0; i < times.size(); i += 4)
      header.times.push_back(std::bit_cast<float>(get_u32(times.data() + i, *format)));
  }
  return header;
}

}  // namespace sweepd::io
