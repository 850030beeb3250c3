// Tests for io::write_png / io::encode_png: decoded again with stb_image, the pixels come back
// unchanged in the same row order; bad buffers and paths give reasons.
#include "io/png/png_write.h"

#include <gtest/gtest.h>
#include <stb/stb_image.h>  // implemented in Debian's libstb
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;

// 5 x 3 pixels, every byte different, so a swapped row or channel shows.
std::vector<std::uint8_t> test_image() {
  std::vector<std::uint8_t> rgba(5 * 3 * 4);
  for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = static_cast<std::uint8_t>(i * 3 + 1);
  return rgba;
}

std::vector<std::uint8_t> decode(const std::uint8_t* data, int size, int& width, int& height) {
  int channels = 0;
  stbi_uc* pixels = stbi_load_from_memory(data, size, &width, &height, &channels, 4);
  if (pixels == nullptr) return {};
  std::vector<std::uint8_t> rgba(pixels, pixels + width * height * 4);
  stbi_image_free(pixels);
  return rgba;
}

TEST(PngWrite, BytesDecodeToTheSamePixelsTopRowFirst) {
  const std::vector<std::uint8_t> rgba = test_image();
  std::vector<std::uint8_t> bytes;
  encode_png(5, 3, rgba, bytes);
  ASSERT_GE(bytes.size(), 8u);
  EXPECT_EQ(std::string(bytes.begin() + 1, bytes.begin() + 4), "PNG");
  int width = 0, height = 0;
  EXPECT_EQ(decode(bytes.data(), static_cast<int>(bytes.size()), width, height), rgba);
  EXPECT_EQ(width, 5);
  EXPECT_EQ(height, 3);
}

TEST(PngWrite, FileHoldsTheEncodedBytes) {
  const fs::path file =
      fs::temp_directory_path() / ("sweepd_png_test_" + std::to_string(::getpid()) + ".png");
  const std::vector<std::uint8_t> rgba = test_image();
  write_png(file, 5, 3, rgba);
  int width = 0, height = 0, channels = 0;
  stbi_uc* pixels = stbi_load(file.c_str(), &width, &height, &channels, 4);
  ASSERT_NE(pixels, nullptr) << stbi_failure_reason();
  EXPECT_EQ(std::vector<std::uint8_t>(pixels, pixels + width * height * 4), rgba);
  stbi_image_free(pixels);
  fs::remove(file);
}

TEST(PngWrite, BadBufferOrPathSaysWhy) {
  std::vector<std::uint8_t> bytes;
  const std::vector<std::uint8_t> rgba = test_image();
  EXPECT_THROW(encode_png(6, 3, rgba, bytes), std::invalid_argument);
  EXPECT_THROW(encode_png(0, 0, {}, bytes), std::invalid_argument);
  const fs::path unwritable = fs::temp_directory_path() / "sweepd_no_such_folder" / "x.png";
  try {
    write_png(unwritable, 5, 3, rgba);
    FAIL() << "writing into a missing folder succeeded";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(unwritable.string()), std::string::npos);
  }
}

}  // namespace
}  // namespace sweepd::io
