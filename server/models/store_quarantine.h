// Store quarantine: where the model store (model_registry.h) puts what it cannot load, so that
// a damaged file is kept for a person to look at, never deleted, and never loaded again.
//
// quarantine(file, store_dir): moves `file` to store_dir/quarantine/<file name>.<UTC time>
//   (e.g. quarantine/3.sweepbind.20261124T193000Z; .1, .2, ... appended when that name is
//   taken), fsyncs both directories and returns the new path. Throws std::filesystem_error when
//   the move fails.
// remove_temporary_files(store_dir): removes the store's FILE.tmp files (io/durable_file.h):
//   each was left by a crash before its rename and never held a committed state. Returns the
//   removed paths.
#pragma once

#include <filesystem>
#include <vector>

namespace sweepd::server {

std::filesystem::path quarantine(const std::filesystem::path& file,
                                 const std::filesystem::path& store_dir);

std::vector<std::filesystem::path> remove_temporary_files(const std::filesystem::path& store_dir);

}  // namespace sweepd::server
