// write_file_durably: replaces a file so that a crash (even kill -9 or power loss) leaves
// either the old contents or the new ones: writes FILE.tmp, fsyncs it, renames it over FILE,
// and fsyncs the directory; writes interrupted by a signal (EINTR) are retried.
//
// Inputs: file path, bytes (any size). Used for .sweepbind files (io/sweepbind.h), the
// server's model store and its port file.
// Throws std::runtime_error "cannot write FILE (step: system reason)"; the descriptor is closed
// on every path.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace sweepd::io {

void write_file_durably(const std::filesystem::path& file, std::span<const std::uint8_t> bytes);

}  // namespace sweepd::io
