#include "cli/video_encoder.h"

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>

namespace sweepd::cli {

namespace {

// Single quotes for the shell, each ' written as '\''.
std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

std::filesystem::path find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream directories(path ? path : "");
  for (std::string directory; std::getline(directories, directory, ':');) {
    const std::filesystem::path candidate = std::filesystem::path(directory) / name;
    if (!directory.empty() && access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

VideoEncoder::VideoEncoder(const std::filesystem::path& file, int width, int height,
                           int frames_per_second)
    : file_(file), frame_bytes_(static_cast<std::size_t>(width) * height * 4) {
  const std::filesystem::path ffmpeg = find_on_path("ffmpeg");
  if (ffmpeg.empty())
    throw std::runtime_error(file.string() +
                             ": --video needs ffmpeg, which is not on PATH (Debian: apt-get "
                             "install ffmpeg; deploy/install-deps.sh installs it)");
  const std::string command =
      shell_quoted(ffmpeg.string()) +
      " -hide_banner -loglevel error -y -f rawvideo -pix_fmt rgba -s " + std::to_string(width) +
      "x" + std::to_string(height) + " -r " + std::to_string(frames_per_second) +
      " -i - -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -pix_fmt yuv420p -movflags "
      "+faststart " +
      shell_quoted(file.string());
  pipe_ = popen(command.c_str(), "w");
  if (pipe_ == nullptr) throw std::runtime_error(file.string() + ": could not start ffmpeg");
  // A failed ffmpeg closes its end: writing must then fail with EPIPE, not kill sweepctl.
  std::signal(SIGPIPE, SIG_IGN);
}

VideoEncoder::~VideoEncoder() {
  if (pipe_ != nullptr) pclose(pipe_);
}

void VideoEncoder::add_frame(std::span<const std::uint8_t> rgba) {
  if (rgba.size() != frame_bytes_)
    throw std::invalid_argument("VideoEncoder: a frame of " + std::to_string(rgba.size()) +
                                " bytes, expected " + std::to_string(frame_bytes_));
  if (std::fwrite(rgba.data(), 1, rgba.size(), pipe_) != rgba.size())
    throw std::runtime_error(file_.string() + ": ffmpeg stopped taking frames (see its message)");
}

void VideoEncoder::finish() {
  const int status = pclose(pipe_);
  pipe_ = nullptr;
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error(file_.string() + ": ffmpeg failed (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                             "; its message is above)");
}

}  // namespace sweepd::cli
