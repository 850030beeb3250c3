// ClientRun: runs a sweepd client example (stream_poses in C++ or Python, render_frames)
// as a child process and reads its report, for the integration tests.
//   run_client(command)   the command line run by the shell, stdout and stderr together
//   pose_counts(output)   {sent, answered, dropped, errors} from the report's "poses:" line,
//                         {-1, -1, -1, -1} when there is none
//   render_counts(output) {rendered, skipped, total, retried, failed} from render_frames' last
//                         line, all -1 when there is none
//   exr_files(directory)  how many .exr files it holds (0 when it does not exist)
// Defined in client_run.cpp (the library test_daemon_process): inline, std::regex cost each of
// the 12 files that include this header about 11 s of compile time under ASan.
#pragma once

#include <array>
#include <filesystem>
#include <string>

namespace sweepd::test {

struct ClientRun {
  int exit_code = -1;
  std::string output;
};

ClientRun run_client(const std::string& command);
std::array<int, 4> pose_counts(const std::string& output);
std::array<int, 5> render_counts(const std::string& output);
int exr_files(const std::filesystem::path& directory);

}  // namespace sweepd::test
