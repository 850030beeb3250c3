#include "server/services/vmc/osc_packet.h"

#include <cstdint>
#include <cstring>

namespace sweepd::server {
namespace {

constexpr char kBundleTag[8] = {'#', 'b', 'u', 'n', 'd', 'l', 'e', '\0'};
constexpr std::size_t kBundleHeader = sizeof(kBundleTag) + 8;  // the tag, then the time tag

bool is_bundle(std::span<const std::byte> bytes) {
  return bytes.size() >= sizeof(kBundleTag) &&
         std::memcmp(bytes.data(), kBundleTag, sizeof(kBundleTag)) == 0;
}

std::uint32_t big_endian_u32(const std::byte* at) {
  return (std::to_integer<std::uint32_t>(at[0]) << 24) |
         (std::to_integer<std::uint32_t>(at[1]) << 16) |
         (std::to_integer<std::uint32_t>(at[2]) << 8) | std::to_integer<std::uint32_t>(at[3]);
}

bool read_message(std::span<std::byte> bytes, OscPacket& packet) {
  int result = 0;
  lo_message message = lo_message_deserialise(bytes.data(), bytes.size(), &result);
  if (message == nullptr) return false;
  OscMessage read;
  read.message.reset(message);
  // The address is the packet's first string: lo_message_deserialise has checked it ends in
  // the packet.
  read.address = reinterpret_cast<const char*>(bytes.data());
  read.types = lo_message_get_types(message);
  packet.messages.push_back(std::move(read));
  return true;
}

bool read_element(std::span<std::byte> bytes, int depth, OscPacket& packet) {
  if (!is_bundle(bytes)) return read_message(bytes, packet);
  if (depth >= kMaxOscBundleDepth || bytes.size() < kBundleHeader) return false;
  ++packet.bundles;
  std::size_t at = kBundleHeader;
  while (at < bytes.size()) {
    if (bytes.size() - at < 4) return false;
    const std::uint32_t size = big_endian_u32(bytes.data() + at);
    at += 4;
    // OSC 1.0: an element's size is a multiple of 4 and the element lies inside its bundle.
    if (size == 0 || size % 4 != 0 || size > bytes.size() - at) return false;
    if (!read_element(bytes.subspan(at, size), depth + 1, packet)) return false;
    at += size;
  }
  return true;
}

}  // namespace

std::optional<OscPacket> read_osc_packet(std::span<std::byte> bytes) {
  OscPacket packet;
  if (bytes.empty() || !read_element(bytes, 0, packet)) return std::nullopt;
  return packet;
}

}  // namespace sweepd::server
