// What a hostile peer sends, for the tests and server_bench that play one: a bare length
// prefix (a frame announced, its body never or slowly sent) and a whole frame of 24 bytes that
// is no message (its file identifier is not "SWPD"), answered with a non-fatal Error until
// max_frame_errors of them close the connection.
#pragma once

#include <cstdint>
#include <vector>

namespace sweepd::protocol {

inline std::vector<std::uint8_t> length_prefix(std::uint32_t length) {
  return {static_cast<std::uint8_t>(length), static_cast<std::uint8_t>(length >> 8),
          static_cast<std::uint8_t>(length >> 16), static_cast<std::uint8_t>(length >> 24)};
}

inline std::vector<std::uint8_t> garbage_frame() {
  std::vector<std::uint8_t> frame = length_prefix(24);
  frame.resize(28, 0xee);
  return frame;
}

}  // namespace sweepd::protocol
