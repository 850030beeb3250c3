// write_file_durably: replaces a file so that a crash (even kill -9 or power loss) leaves
// either the old contents or the new ones: writes FILE.tmp, fsyncs it, renames it over FILE,
// and fsyncs the directory. Throws std::runtime_error naming the file and the system reason.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace sweepd::server {

void write_file_durably(const std::filesystem::path& file, std::span<const std::uint8_t> bytes);

}  // namespace sweepd::server
