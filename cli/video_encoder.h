// VideoEncoder: an H.264 .mp4 from raw RGBA frames, piped to Debian's ffmpeg (sweepctl sheet
// --video). ffmpeg is looked up on PATH; deploy/install-deps.sh installs it.
//
// VideoEncoder(file, width W, height H, frames per second): starts ffmpeg writing `file`
//   (odd sizes are padded by one pixel: H.264's 4:2:0 wants even ones). Throws
//   std::runtime_error saying ffmpeg is missing when it is not on PATH.
// add_frame(rgba): one frame, W·H·4 bytes, row 0 = top. finish(): closes the pipe and waits;
//   throws std::runtime_error when ffmpeg failed (its own messages are on stderr). The
//   destructor of an unfinished encoder closes the pipe without checking.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <span>

namespace sweepd::cli {

class VideoEncoder {
 public:
  VideoEncoder(const std::filesystem::path& file, int width, int height, int frames_per_second);
  ~VideoEncoder();
  VideoEncoder(const VideoEncoder&) = delete;
  VideoEncoder& operator=(const VideoEncoder&) = delete;

  void add_frame(std::span<const std::uint8_t> rgba);
  void finish();

 private:
  std::filesystem::path file_;
  std::size_t frame_bytes_;
  FILE* pipe_ = nullptr;
};

// The first executable `name` in the directories of PATH; empty when there is none.
std::filesystem::path find_on_path(const std::string& name);

}  // namespace sweepd::cli
