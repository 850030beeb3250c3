#include "tests/server/client_run.h"

#include <regex>

#include "tests/deploy/shell_command.h"

namespace sweepd::test {

ClientRun run_client(const std::string& command) {
  const CommandResult result = run_command(command);
  return {result.exit_code, result.output};
}

std::array<int, 4> pose_counts(const std::string& output) {
  std::smatch match;
  const std::regex line(R"(poses: sent (\d+), answered (\d+), dropped (\d+), errors (\d+))");
  if (!std::regex_search(output, match, line)) return {-1, -1, -1, -1};
  return {std::stoi(match[1]), std::stoi(match[2]), std::stoi(match[3]), std::stoi(match[4])};
}

std::array<int, 5> render_counts(const std::string& output) {
  std::smatch m;
  const std::regex line(
      R"(rendered (\d+), skipped (\d+) of (\d+) frames in [0-9.]+ s \([0-9.]+ frames/s\), )"
      R"(retried (\d+), failed (\d+))");
  if (!std::regex_search(output, m, line)) return {-1, -1, -1, -1, -1};
  return {std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4]), std::stoi(m[5])};
}

int exr_files(const std::filesystem::path& directory) {
  int count = 0;
  if (std::filesystem::exists(directory))
    for (const auto& entry : std::filesystem::directory_iterator(directory))
      count += entry.path().extension() == ".exr";
  return count;
}

}  // namespace sweepd::test
