#include "io/assimp/assimp_crash_guard.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <thread>

#include "io/assimp/assimp_scene.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SWEEPD_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define SWEEPD_SANITIZED 1
#endif
#endif
#ifdef SWEEPD_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif

namespace sweepd::io {
namespace {

// A crash in the child is the guard at work, not a finding in sweepd: under a sanitizer its
// report goes to the child's stderr instead of the log_path folder .ci/sanitized_ctest fails
// on, and a fuzzer's death callback (which would save the input as a crash of its own) is not
// run. libFuzzer's crash handlers are also signal handlers the child inherits (an assimp
// ai_assert's abort() ran them, and saved 7 inputs of one contained crash as findings): the
// fatal signals go back to their default action, so the child just dies of them. The parent
// still hears of the crash from the exit status.
void quiet_crash_handlers_in_child() {
#ifdef SWEEPD_SANITIZED
  __sanitizer_set_report_fd(reinterpret_cast<void*>(static_cast<std::intptr_t>(STDERR_FILENO)));
  __sanitizer_set_death_callback(nullptr);
#endif
  for (const int fatal : {SIGABRT, SIGSEGV, SIGBUS, SIGILL, SIGFPE}) ::signal(fatal, SIG_DFL);
}

}  // namespace

std::string assimp_import_crash(std::span<const std::uint8_t> bytes, int seconds) {
  const pid_t child = fork();
  if (child < 0)
    return std::string("the importer could not be tried in a child process: ") +
           std::strerror(errno);
  if (child == 0) {
    quiet_crash_handlers_in_child();
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
  for (auto pause = std::chrono::microseconds(200);;
       pause = std::min(2 * pause, decltype(pause)(20000))) {
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
  // The child exits 0 after any import; another status is a crash reported by a handler that
  // exits instead of dying of the signal (a sanitizer's, or a fuzzer's).
  if (WEXITSTATUS(status) != 0)
    return "the importer crashed on this file (exit status " + std::to_string(WEXITSTATUS(status)) +
           ")";
  return "";
}

}  // namespace sweepd::io
