// ClientRun: runs a sweepd client example (stream_poses in C++ or Python, render_frames)
// as a child process and reads its report, for the integration tests.
//   run_client(command)   the command line run by the shell, stdout and stderr together
//   pose_counts(output)   {sent, answered, dropped, errors} from the report's "poses:" line,
//                         {-1, -1, -1, -1} when there is none
//   render_counts(output) {rendered, skipped, total, retried, failed} from render_frames' last
//                         line, all -1 when there is none
//   exr_files(directory)  how many .exr files it holds (0 when it does not exist)
#pragma once

#include <array>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>

#include "tests/deploy/shell_command.h"

namespace sweepd::test {

struct ClientRun {
  int exit_code = -1;
  std::string output;
};

inline ClientRun run_client(const std::string& command) {
  const CommandResult result = run_command(command);
  return {result.exit_code, result.output};
}

inline std::array<int, 4> pose_counts(const std::string& output) {
  std::smatch match;
  const std::regex line(R"(poses: sent (\d+), answered (\d+), dropped (\d+), errors (\d+))");
  if (!std::regex_search(output, match, line)) return {-1, -1, -1, -1};
  return {std::stoi(match[1]), std::stoi(match[2]), std::stoi(match[3]), std::stoi(match[4])};
}

inline std::array<int, 5> render_counts(const std::string& output) {
  std::smatch m;
  const std::regex line(
      R"(rendered (\d+), skipped (\d+) of (\d+) frames in [0-9.]+ s \([0-9.]+ frames/s\), )"
      R"(retried (\d+), failed (\d+))");
  if (!std::regex_search(output, m, line)) return {-1, -1, -1, -1, -1};
  return {std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4]), std::stoi(m[5])};
}

inline int exr_files(const std::filesystem::path& directory) {
  int count = 0;
  if (std::filesystem::exists(directory))
    for (const auto& entry : std::filesystem::directory_iterator(directory))
      count += entry.path().extension() == ".exr";
  return count;
}

}  // namespace sweepd::test
