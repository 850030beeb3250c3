// Whole-file reads for the loaders and the clients: a file's bytes (models, .sweepbind, uploads)
// or its text (BVH clips, rig and name maps sent to a server), or a LoadError that names the file
// and says why it could not be read (missing, a directory, unreadable).
//
//   file  the file to read
// Returns every byte of it; an empty file gives an empty result (the caller decides if that is
// an error).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sweepd::io {

std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& file);
std::string read_file_text(const std::filesystem::path& file);

}  // namespace sweepd::io
