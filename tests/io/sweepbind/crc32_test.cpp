// Tests for io::crc32 (zlib's CRC-32, stored in .sweepbind headers): the catalogue check value
// of CRC-32/ISO-HDLC and the empty input, exact (an integer checksum has no tolerance).
#include <gtest/gtest.h>

#include <string_view>

#include "io/sweepbind/byte_stream.h"

namespace sweepd::io {
namespace {

std::uint32_t crc_of(std::string_view text) {
  return crc32(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

TEST(Crc32, MatchesTheCatalogueCheckValue) {
  EXPECT_EQ(crc_of("123456789"), 0xCBF43926u);
  EXPECT_EQ(crc_of(""), 0u);
}

}  // namespace
}  // namespace sweepd::io
