// write_png / encode_png: 8-bit RGBA images (previews) as PNG files or PNG bytes in memory.
//
// Input:  width W, height H, rgba W·H·4 bytes, row-major, row 0 = the image's top row.
// Output: an RGBA PNG (zlib compressed, via stb_image_write).
// Throws std::invalid_argument when the buffer does not hold W·H·4 bytes, std::runtime_error
// (naming the file and the reason) when the file cannot be written.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace sweepd::io {

void write_png(const std::filesystem::path& file, int width, int height,
               std::span<const std::uint8_t> rgba);

// The same file's bytes, into a caller-owned vector (cleared first).
void encode_png(int width, int height, std::span<const std::uint8_t> rgba,
                std::vector<std::uint8_t>& bytes);

}  // namespace sweepd::io
