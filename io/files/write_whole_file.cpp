#include "io/files/write_whole_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>

namespace sweepd::io {

void write_whole_file(const std::filesystem::path& file, std::span<const std::uint8_t> bytes,
                      const char* writer) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (out) {
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    out.close();
  }
  if (!out) {
    throw std::runtime_error(std::string(writer) + " " + file.string() +
                             ": cannot write the file (" + std::strerror(errno) + ")");
  }
}

void write_whole_file(const std::filesystem::path& file, std::string_view text,
                      const char* writer) {
  write_whole_file(file, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}, writer);
}

}  // namespace sweepd::io
