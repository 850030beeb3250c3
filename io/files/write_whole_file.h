// write_whole_file: writes bytes encoded in memory (EXR, PNG) to a file, replacing it.
//
// Inputs: file path, bytes, and the writer's name for the message ("write_exr").
// Throws std::runtime_error "<writer> <file>: cannot write the file (<system reason>)".
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace sweepd::io {

void write_whole_file(const std::filesystem::path& file, std::span<const std::uint8_t> bytes,
                      const char* writer);

}  // namespace sweepd::io
