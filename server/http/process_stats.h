// ProcessStats: what the kernel says of this process, for /metrics — its resident memory
// (/proc/self/statm: resident pages × page size) and its start time in seconds since the Unix
// epoch (/proc/self/stat's start in clock ticks after boot, plus /proc/stat's btime).
// read_process_stats(): reads both now; a field that cannot be read is 0.
#pragma once

#include <cstdint>

namespace sweepd::server {

struct ProcessStats {
  std::uint64_t resident_bytes = 0;
  double start_time_seconds = 0.0;
};

ProcessStats read_process_stats();

}  // namespace sweepd::server
