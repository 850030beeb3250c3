#include "server/http/process_stats.h"

#include <unistd.h>

#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace sweepd::server {
namespace {

std::uint64_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::uint64_t total_pages = 0, resident_pages = 0;
  if (!(statm >> total_pages >> resident_pages)) return 0;
  return resident_pages * static_cast<std::uint64_t>(sysconf(_SC_PAGESIZE));
}

// Seconds since the epoch at which the machine booted (/proc/stat "btime").
double boot_time_seconds() {
  std::ifstream stat("/proc/stat");
  std::string key;
  double value = 0.0;
  while (stat >> key) {
    if (key == "btime") {
      stat >> value;
      return value;
    }
    stat.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return 0.0;
}

double start_time_seconds() {
  std::ifstream stat_file("/proc/self/stat");
  std::string line;
  std::getline(stat_file, line);
  // Field 2 (the command name) may hold spaces: count fields after its closing parenthesis.
  const std::size_t name_end = line.rfind(')');
  if (name_end == std::string::npos) return 0.0;
  std::istringstream fields(line.substr(name_end + 2));
  std::string field;
  // The rest starts at field 3 (state); the start time is field 22.
  for (int index = 3; index < 22; ++index) fields >> field;
  double start_ticks = 0.0;
  if (!(fields >> start_ticks)) return 0.0;
  return boot_time_seconds() + start_ticks / static_cast<double>(sysconf(_SC_CLK_TCK));
}

}  // namespace

ProcessStats read_process_stats() { return {resident_bytes(), start_time_seconds()}; }

}  // namespace sweepd::server
