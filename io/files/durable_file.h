// write_file_durably: replaces a file so that a crash (even kill -9 or power loss) leaves
// either the old contents or the new ones: writes FILE.<pid>@<host>.tmp, fsyncs it, renames it
// over FILE, and fsyncs the directory; writes interrupted by a signal (EINTR) are retried. The
// temporary's name is the writer's own, so processes on several hosts writing one file of a
// shared directory at once never write into each other's temporary: each rename is whole.
//
// Inputs: file path, bytes (any size). Used for .sweepbind files (io/sweepbind/sweepbind.h), the
// server's model store and its port file.
// Throws std::runtime_error "cannot write FILE (step: system reason)"; the descriptor is closed
// on every path.
//
// sync_directory: fsyncs a directory, so that the renames and removals made in it so far
// survive a crash; a directory that cannot be opened is left alone (best effort, as above).
// kTemporarySuffix: the suffix of write_file_durably's temporaries; one whose writer is gone was
// left by a crash before its rename and never holds a committed state.
// temporary_writer(file): the pid and host a temporary's name gives (pid 0: a name without
//   them, from before they were written into it).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace sweepd::io {

inline constexpr std::string_view kTemporarySuffix = ".tmp";

void write_file_durably(const std::filesystem::path& file, std::span<const std::uint8_t> bytes);

struct TemporaryWriter {
  long pid = 0;
  std::string host;
};
TemporaryWriter temporary_writer(const std::filesystem::path& file);
std::string this_host();
void sync_directory(const std::filesystem::path& directory);

}  // namespace sweepd::io
