// Store quarantine: where the model store (model_registry.h) puts what it cannot load, so that
// a damaged file is kept for a person to look at, never deleted, and never loaded again.
//
// quarantine(file, store_dir): moves `file` to store_dir/quarantine/<file name>.<UTC time>
//   (e.g. quarantine/3.sweepbind.20261124T193000Z; .1, .2, ... appended when that name is
//   taken), fsyncs both directories and returns the new path. Throws std::filesystem_error when
//   the move fails.
// remove_temporary_files(store_dir): removes the store's temporaries (io/files/durable_file.h) whose
//   writer is gone — written on this host by a process that no longer runs, untouched for an
//   hour (another host's crash: a store shared by replicas), or named FILE.tmp by an older
//   sweepd — each left by a crash before its
//   rename, never a committed state. Another live writer's temporary is left alone. Returns
//   the removed paths.
#pragma once

#include <filesystem>
#include <vector>

namespace sweepd::server {

std::filesystem::path quarantine(const std::filesystem::path& file,
                                 const std::filesystem::path& store_dir);

std::vector<std::filesystem::path> remove_temporary_files(const std::filesystem::path& store_dir);

}  // namespace sweepd::server
