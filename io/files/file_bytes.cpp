#include "io/files/file_bytes.h"

#include <fstream>
#include <iterator>

#include "io/files/load_error.h"

namespace sweepd::io {

namespace {

// Opens `file` for reading, or throws why it cannot be.
std::ifstream open_for_reading(const std::filesystem::path& file) {
  std::error_code error;
  if (std::filesystem::is_directory(file, error))
    throw LoadError(file, "is a directory, not a file");
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw LoadError(file, "cannot open the file (missing or unreadable)");
  return stream;
}

}  // namespace

std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& file) {
  std::ifstream stream = open_for_reading(file);
  return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
}

std::string read_file_text(const std::filesystem::path& file) {
  std::ifstream stream = open_for_reading(file);
  return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
}

}  // namespace sweepd::io
