// run_command(command): runs `command` with /bin/sh (stderr folded into stdout) and returns
// what it printed and its exit code (-1 when it did not exit normally), for the deploy tests
// that call the operators' own checkers (haproxy -c, systemd-analyze, kubectl, podman, node).
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>
#include <utility>

namespace sweepd::test {

struct CommandResult {
  std::string output;
  int exit_code = -1;
};

inline CommandResult run_command(const std::string& command) {
  CommandResult result;
  FILE* pipe = popen(("(" + command + ") 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  char chunk[4096];
  while (const std::size_t n = std::fread(chunk, 1, sizeof(chunk), pipe)) {
    result.output.append(chunk, n);
  }
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace sweepd::test
