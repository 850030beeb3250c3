#include "io/png/png_write.h"

#include <stb/stb_image_write.h>  // implemented in Debian's libstb

#include <stdexcept>
#include <string>

#include "io/files/write_whole_file.h"

namespace sweepd::io {
namespace {

void append_bytes(void* context, void* data, int size) {
  auto& bytes = *static_cast<std::vector<std::uint8_t>*>(context);
  const auto* begin = static_cast<const std::uint8_t*>(data);
  bytes.insert(bytes.end(), begin, begin + size);
}

}  // namespace

void encode_png(int width, int height, std::span<const std::uint8_t> rgba,
                std::vector<std::uint8_t>& bytes) {
  if (width < 1 || height < 1 ||
      rgba.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4) {
    throw std::invalid_argument("PNG image: " + std::to_string(rgba.size()) +
                                " bytes do not hold " + std::to_string(width) + "x" +
                                std::to_string(height) + " RGBA pixels");
  }
  bytes.clear();
  if (stbi_write_png_to_func(append_bytes, &bytes, width, height, 4, rgba.data(), width * 4) == 0) {
    throw std::runtime_error("PNG image: stb_image_write could not encode it");
  }
}

void write_png(const std::filesystem::path& file, int width, int height,
               std::span<const std::uint8_t> rgba) {
  std::vector<std::uint8_t> bytes;
  encode_png(width, height, rgba, bytes);
  write_whole_file(file, bytes, "write_png");
}

}  // namespace sweepd::io
