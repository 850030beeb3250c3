// write_whole_file: writes bytes encoded in memory (EXR, PNG, a contact sheet, a server's
// reply) to the file a user names, replacing it, in place: the file may be a FIFO or a device
// (a model store's files, which a crash must not leave half written, go through
// io/files/durable_file.h instead).
//
// Inputs: file path, bytes, and the writer's name for the message ("write_exr").
// Throws std::runtime_error "<writer> <file>: cannot write the file (<system reason>)".
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

namespace sweepd::io {

void write_whole_file(const std::filesystem::path& file, std::span<const std::uint8_t> bytes,
                      const char* writer);
// The same for text (a JSON file).
void write_whole_file(const std::filesystem::path& file, std::string_view text, const char* writer);

}  // namespace sweepd::io
