#include "io/assimp_crash_guard.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include "io/assimp_scene.h"

namespace sweepd::io {

std::string assimp_import_crash(std::span<const std::uint8_t> bytes, int seconds) {
  const pid_t child = fork();
  if (child < 0)
    return std::string("the importer could not be tried in a child process: ") +
           std::strerror(errno);
  if (child == 0) {
    try {
      Assimp::Importer importer;
      assimp::configure_importer(importer, true);
      importer.ReadFileFromMemory(bytes.data(), bytes.size(), assimp::kImportSteps,
                                  assimp::sniff(bytes) == assimp::Format::kFbx ? "fbx" : "dae");
    } catch (...) {
      // A clean refusal: the caller's own read names it.
    }
    _exit(0);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  int status = 0;
  for (auto pause = std::chrono::microseconds(200);; pause = std::min(2 * pause, decltype(pause)(20000))) {
    const pid_t done = waitpid(child, &status, WNOHANG);
    if (done == child) break;
    if (done < 0 && errno != EINTR)
      return std::string("the importer's child process was lost: ") + std::strerror(errno);
    if (std::chrono::steady_clock::now() > deadline) {
      kill(child, SIGKILL);
      waitpid(child, &status, 0);
      return "the importer took more than " + std::to_string(seconds) + " s on this file";
    }
    std::this_thread::sleep_for(pause);
  }
  if (WIFSIGNALED(status))
    return "the importer crashed on this file (signal " + std::to_string(WTERMSIG(status)) + ")";
  return "";
}

}  // namespace sweepd::io
