// Running sweepctl as a user does, for the tests of tests/cli: a real process (SWEEPD_SWEEPCTL),
// its printed report and exit code, the shared data (SWEEPD_SHARED_DATA) and a scratch folder.
//   run_sweepctl(arguments, streams, environment)  streams: the shell redirections ("2>&1":
//     stdout and stderr together); environment: VAR=value assignments put before the command
//   shared(relative)   a path under ../shared/data
//   process_scratch(name) (tests/scratch_directory.h): the scratch folder
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include "tests/scratch_directory.h"
#include "tests/test_paths.h"

namespace sweepd::test {

struct SweepctlResult {
  int exit_code;
  std::string output;  // stdout and stderr together, or what `streams` leaves
};

inline SweepctlResult run_sweepctl(const std::string& arguments,
                                   const std::string& streams = "2>&1",
                                   const std::string& environment = "") {
  const std::string command =
      environment + std::string(SWEEPD_SWEEPCTL) + " " + arguments + " " + streams;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string output;
  std::array<char, 4096> buffer;
  while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe))
    output.append(buffer.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

inline std::filesystem::path shared(const std::string& relative) {
  return std::filesystem::path(SWEEPD_SHARED_DATA) / relative;
}

}  // namespace sweepd::test
