#include "server/models/store_quarantine.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <ctime>
#include <string>

#include "io/files/durable_file.h"

namespace sweepd::server {

namespace fs = std::filesystem;

fs::path quarantine(const fs::path& file, const fs::path& store_dir) {
  const fs::path folder = store_dir / "quarantine";
  fs::create_directories(folder);
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%dT%H%M%SZ", &utc);
  const std::string base = file.filename().string() + "." + std::string(stamp);
  fs::path target = folder / base;
  for (int n = 1; fs::exists(target); ++n) target = folder / (base + "." + std::to_string(n));
  fs::rename(file, target);
  io::sync_directory(folder);
  io::sync_directory(file.parent_path());
  return target;
}

namespace {

// Whether the temporary's writer is gone (see the header).
bool writer_gone(const fs::directory_entry& temporary) {
  const io::TemporaryWriter writer = io::temporary_writer(temporary.path());
  if (writer.pid == 0) return true;  // FILE.tmp: written by a sweepd older than this one
  if (writer.host == io::this_host()) {
    return writer.pid != getpid() && kill(static_cast<pid_t>(writer.pid), 0) != 0 && errno == ESRCH;
  }
  std::error_code error;
  const auto modified = temporary.last_write_time(error);
  return !error && fs::file_time_type::clock::now() - modified > std::chrono::hours(1);
}

}  // namespace

std::vector<fs::path> remove_temporary_files(const fs::path& store_dir) {
  std::vector<fs::path> removed;
  for (const fs::directory_entry& entry : fs::directory_iterator(store_dir)) {
    if (entry.is_regular_file() && entry.path().string().ends_with(io::kTemporarySuffix) &&
        writer_gone(entry)) {
      removed.push_back(entry.path());
    }
  }
  for (const fs::path& file : removed) fs::remove(file);
  if (!removed.empty()) io::sync_directory(store_dir);
  return removed;
}

}  // namespace sweepd::server
