#include <zlib.h>

#include "io/sweepbind/byte_stream.h"

namespace sweepd::io {

// zlib's crc32_z is the same CRC-32 (reflected polynomial 0xEDB88320, initial and final
// 0xFFFFFFFF) the .sweepbind header has always stored; z_size_t takes spans past 4 GiB whole.
std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  return static_cast<std::uint32_t>(
      ::crc32_z(::crc32_z(0L, Z_NULL, 0), bytes.data(), bytes.size()));
}

}  // namespace sweepd::io
