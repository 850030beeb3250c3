// ClientRun: runs a sweepd client example (the C++ stream_poses or the Python
// stream_poses.py) as a child process and reads its report, for the integration tests.
//   run_client(command)   the command line run by the shell, stdout and stderr together
//   pose_counts(output)   {sent, answered, dropped, errors} from the report's "poses:" line,
//                         {-1, -1, -1, -1} when there is none
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <regex>
#include <string>

namespace sweepd::test {

struct ClientRun {
  int exit_code = -1;
  std::string output;
};

inline ClientRun run_client(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return {};
  ClientRun run;
  std::array<char, 4096> buffer;
  while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) {
    run.output.append(buffer.data(), n);
  }
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

inline std::array<int, 4> pose_counts(const std::string& output) {
  std::smatch match;
  const std::regex line(R"(poses: sent (\d+), answered (\d+), dropped (\d+), errors (\d+))");
  if (!std::regex_search(output, match, line)) return {-1, -1, -1, -1};
  return {std::stoi(match[1]), std::stoi(match[2]), std::stoi(match[3]), std::stoi(match[4])};
}

}  // namespace sweepd::test
