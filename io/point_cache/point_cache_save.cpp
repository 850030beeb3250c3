#include "io/point_cache/point_cache_save.h"

#include <bit>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>

namespace sweepd::io {

namespace {

float byte_swapped(float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  return std::bit_cast<float>((bits >> 24) | ((bits >> 8) & 0xff00u) | ((bits << 8) & 0xff0000u) |
                              (bits << 24));
}

std::string file_problem(const std::filesystem::path& file, const std::string& reason) {
  return "point cache " + file.string() + ": " + reason;
}

void check_header(const std::filesystem::path& file, const PointCacheHeader& header) {
  auto refuse = [&](const std::string& reason) {
    throw std::invalid_argument(file_problem(file, reason));
  };
  if (header.point_count <= 0)
    refuse("no points to cache (point count " + std::to_string(header.point_count) + ")");
  if (header.frame_count <= 0)
    refuse("no frames to cache (frame count " + std::to_string(header.frame_count) + ")");
  // The format's counts are 32-bit signed ints: keep a frame's bytes (points * 12) within one
  // as well, so no reader's offset arithmetic overflows within a frame.
  if (header.point_count > (INT32_MAX / 12))
    refuse(std::to_string(header.point_count) + " points do not fit the format's 32-bit sizes");
  if (header.format == PointCacheFormat::kMdd &&
      header.times.size() != static_cast<std::size_t>(header.frame_count))
    refuse(std::to_string(header.times.size()) + " frame times for " +
           std::to_string(header.frame_count) + " frames");
}

PointCacheHeader header_of(const std::filesystem::path& file, const PointCacheLayout& layout) {
  if (layout.first_frame < 0)
    throw std::invalid_argument(file_problem(
        file, "the first frame must be 0 or more, not " + std::to_string(layout.first_frame)));
  if (!(layout.frames_per_second > 0.0))
    throw std::invalid_argument(file_problem(
        file, "the frame rate must be above 0, not " + std::to_string(layout.frames_per_second)));
  PointCacheHeader header{.format = layout.format,
                          .point_count = layout.point_count,
                          .frame_count = layout.frame_count,
                          .start_frame = static_cast<float>(layout.first_frame),
                          .sampling = 1.0f,  // one sample per frame
                          .times = {}};
  if (layout.format == PointCacheFormat::kMdd)
    for (int i = 0; i < std::max(layout.frame_count, 0); ++i)
      header.times.push_back(
          static_cast<float>((layout.first_frame + i) / layout.frames_per_second));
  return header;
}

}  // namespace

const std::map<std::string, PointCacheAxes>& point_cache_axes_names() {
  static const std::map<std::string, PointCacheAxes> names = {
      {"gltf", PointCacheAxes::kGltf}, {"blender", PointCacheAxes::kBlender}};
  return names;
}

PointCacheWriter::PointCacheWriter(const std::filesystem::path& file,
                                   const PointCacheLayout& layout)
    : PointCacheWriter(file, header_of(file, layout), layout.axes) {}

PointCacheWriter::PointCacheWriter(const std::filesystem::path& file,
                                   const PointCacheHeader& header, PointCacheAxes axes)
    : file_(file), header_(header), axes_(axes) {
  check_header(file, header);
  written_.assign(static_cast<std::size_t>(header.frame_count), false);
  partial_ = file;
  partial_ += ".partial";
  out_ = std::fopen(partial_.c_str(), "wb");
  if (out_ == nullptr) fail_system("cannot create it");
  try {
    write_bytes(point_cache_header_bytes(header));
  } catch (...) {
    abandon();
    throw;
  }
}

PointCacheWriter::~PointCacheWriter() { abandon(); }

void PointCacheWriter::abandon() {
  if (out_ == nullptr) return;
  std::fclose(out_);
  out_ = nullptr;
  std::error_code ignored;  // best effort: the run has already failed for its own reason
  std::filesystem::remove(partial_, ignored);
}

void PointCacheWriter::write_frame(std::span<const glm::vec3> positions) {
  if (next_frame_ == header_.frame_count)
    throw std::invalid_argument(file_problem(
        file_, "a frame beyond the " + std::to_string(header_.frame_count) + " promised"));
  write_frame_at(next_frame_, positions);
  ++next_frame_;
}

void PointCacheWriter::write_frame_at(int index, std::span<const glm::vec3> positions) {
  if (positions.size() != static_cast<std::size_t>(header_.point_count))
    throw std::invalid_argument(file_problem(
        file_, "frame " + std::to_string(index) + " has " + std::to_string(positions.size()) +
                   " points, the cache " + std::to_string(header_.point_count)));
  // The floats in the cache's axes, then their bytes in the format's order: two plain loops
  // (the compiler vectorises both), a tenth of a frame's time on the 72k mannequin.
  frame_floats_.resize(positions.size() * 3);
  float* out = frame_floats_.data();
  if (axes_ == PointCacheAxes::kBlender)
    for (const glm::vec3& p : positions) {  // glTF's +Y up is Blender's +Z, its +Z Blender's -Y
      *out++ = p.x;
      *out++ = -p.z;
      *out++ = p.y;
    }
  else
    for (const glm::vec3& p : positions) {
      *out++ = p.x;
      *out++ = p.y;
      *out++ = p.z;
    }
  const bool little = header_.format == PointCacheFormat::kPc2;
  if (little != (std::endian::native == std::endian::little))
    for (float& value : frame_floats_) value = byte_swapped(value);
  write_frame_bytes(index, {reinterpret_cast<const std::uint8_t*>(frame_floats_.data()),
                            frame_floats_.size() * sizeof(float)});
}

void PointCacheWriter::write_frame_bytes(int index, std::span<const std::uint8_t> bytes) {
  if (out_ == nullptr)
    throw std::invalid_argument(file_problem(file_, "a frame written after finish()"));
  if (index < 0 || index >= header_.frame_count)
    throw std::invalid_argument(file_problem(file_, "frame index " + std::to_string(index) +
                                                        " outside the cache's " +
                                                        std::to_string(header_.frame_count)));
  if (bytes.size() != header_.frame_size())
    throw std::invalid_argument(file_problem(
        file_, "frame " + std::to_string(index) + " has " + std::to_string(bytes.size()) +
                   " bytes, the cache's frames " + std::to_string(header_.frame_size())));
  if (written_[static_cast<std::size_t>(index)])
    throw std::invalid_argument(
        file_problem(file_, "frame index " + std::to_string(index) + " written twice"));
  const std::uint64_t offset = header_.header_size() + header_.frame_size() * std::uint64_t(index);
  if (fseeko(out_, static_cast<off_t>(offset), SEEK_SET) != 0) fail_system("cannot seek in it");
  write_bytes(bytes);
  written_[static_cast<std::size_t>(index)] = true;
  ++frames_written_;
}

void PointCacheWriter::finish() {
  if (out_ == nullptr) return;
  if (frames_written_ != header_.frame_count)
    throw std::invalid_argument(
        file_problem(file_, std::to_string(frames_written_) + " frames written of the " +
                                std::to_string(header_.frame_count) + " its header promises"));
  // fclose flushes the last frame: a full disk shows here.
  if (std::fclose(std::exchange(out_, nullptr)) != 0) {
    const int reason = errno;
    std::error_code ignored;
    std::filesystem::remove(partial_, ignored);
    errno = reason;
    fail_system("cannot finish writing it");
  }
  std::error_code renamed;
  std::filesystem::rename(partial_, file_, renamed);
  if (renamed)
    throw std::runtime_error(file_problem(file_, "cannot rename " + partial_.filename().string() +
                                                     " to it (" + renamed.message() + ")"));
}

void PointCacheWriter::write_bytes(std::span<const std::uint8_t> bytes) {
  if (std::fwrite(bytes.data(), 1, bytes.size(), out_) != bytes.size())
    fail_system("cannot write it");
}

void PointCacheWriter::fail_system(const char* step) const {
  throw std::runtime_error(
      file_problem(file_, std::string(step) + " (" + std::strerror(errno) + ")"));
}

}  // namespace sweepd::io
