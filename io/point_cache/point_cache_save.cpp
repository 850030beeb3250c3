#include "io/point_cache/point_cache_save.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>

namespace sweepd::io {

namespace {

// Writes a 32-bit value's bytes in the format's order, whatever the host's: PC2 is
// little-endian, MDD big-endian.
void put_u32(std::uint8_t* out, std::uint32_t bits, PointCacheFormat format) {
  for (int i = 0; i < 4; ++i) {
    const int shift = format == PointCacheFormat::kPc2 ? 8 * i : 8 * (3 - i);
    out[i] = static_cast<std::uint8_t>(bits >> shift);
  }
}

void put_int(std::vector<std::uint8_t>& out, std::int32_t value, PointCacheFormat format) {
  out.resize(out.size() + 4);
  put_u32(out.data() + out.size() - 4, static_cast<std::uint32_t>(value), format);
}

void put_float(std::vector<std::uint8_t>& out, float value, PointCacheFormat format) {
  out.resize(out.size() + 4);
  put_u32(out.data() + out.size() - 4, std::bit_cast<std::uint32_t>(value), format);
}

float byte_swapped(float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  return std::bit_cast<float>((bits >> 24) | ((bits >> 8) & 0xff00u) | ((bits << 8) & 0xff0000u) |
                              (bits << 24));
}

std::string file_problem(const std::filesystem::path& file, const std::string& reason) {
  return "point cache " + file.string() + ": " + reason;
}

void check_layout(const std::filesystem::path& file, const PointCacheLayout& layout) {
  auto refuse = [&](const std::string& reason) {
    throw std::invalid_argument(file_problem(file, reason));
  };
  if (layout.point_count <= 0)
    refuse("no points to cache (point count " + std::to_string(layout.point_count) + ")");
  if (layout.frame_count <= 0)
    refuse("no frames to cache (frame count " + std::to_string(layout.frame_count) + ")");
  if (layout.first_frame < 0)
    refuse("the first frame must be 0 or more, not " + std::to_string(layout.first_frame));
  if (!(layout.frames_per_second > 0.0))
    refuse("the frame rate must be above 0, not " + std::to_string(layout.frames_per_second));
  // The format's counts are 32-bit signed ints: keep a frame's bytes (points * 12) within one
  // as well, so no reader's offset arithmetic overflows within a frame.
  if (layout.point_count > (INT32_MAX / 12))
    refuse(std::to_string(layout.point_count) + " points do not fit the format's 32-bit sizes");
}

std::vector<std::uint8_t> header_bytes(const PointCacheLayout& layout) {
  std::vector<std::uint8_t> header;
  const PointCacheFormat format = layout.format;
  if (format == PointCacheFormat::kPc2) {
    const char signature[12] = "POINTCACHE2";  // 11 letters and the terminating zero
    header.assign(signature, signature + sizeof signature);
    put_int(header, 1, format);  // file version
    put_int(header, layout.point_count, format);
    put_float(header, static_cast<float>(layout.first_frame), format);
    put_float(header, 1.0f, format);  // sampling: one sample per frame
    put_int(header, layout.frame_count, format);
    return header;
  }
  put_int(header, layout.frame_count, format);
  put_int(header, layout.point_count, format);
  for (int i = 0; i < layout.frame_count; ++i)
    put_float(header, static_cast<float>((layout.first_frame + i) / layout.frames_per_second),
              format);
  return header;
}

}  // namespace

std::optional<PointCacheFormat> point_cache_format(const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".pc2") return PointCacheFormat::kPc2;
  if (extension == ".mdd") return PointCacheFormat::kMdd;
  return std::nullopt;
}

PointCacheWriter::PointCacheWriter(const std::filesystem::path& file,
                                   const PointCacheLayout& layout)
    : file_(file), layout_(layout) {
  check_layout(file, layout);
  partial_ = file;
  partial_ += ".partial";
  out_ = std::fopen(partial_.c_str(), "wb");
  if (out_ == nullptr) fail_system("cannot create it");
  try {
    write_bytes(header_bytes(layout));
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
  if (out_ == nullptr)
    throw std::invalid_argument(file_problem(file_, "a frame written after finish()"));
  if (positions.size() != static_cast<std::size_t>(layout_.point_count))
    throw std::invalid_argument(file_problem(file_, "frame " + std::to_string(frames_written_) +
                                                        " has " + std::to_string(positions.size()) +
                                                        " points, the cache " +
                                                        std::to_string(layout_.point_count)));
  if (frames_written_ == layout_.frame_count)
    throw std::invalid_argument(file_problem(
        file_, "a frame beyond the " + std::to_string(layout_.frame_count) + " promised"));
  // The floats in the cache's axes, then their bytes in the format's order: two plain loops
  // (the compiler vectorises both), a tenth of a frame's time on the 72k mannequin.
  frame_floats_.resize(positions.size() * 3);
  float* out = frame_floats_.data();
  if (layout_.axes == PointCacheAxes::kBlender)
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
  const bool little = layout_.format == PointCacheFormat::kPc2;
  if (little != (std::endian::native == std::endian::little))
    for (float& value : frame_floats_) value = byte_swapped(value);
  write_bytes({reinterpret_cast<const std::uint8_t*>(frame_floats_.data()),
               frame_floats_.size() * sizeof(float)});
  ++frames_written_;
}

void PointCacheWriter::finish() {
  if (out_ == nullptr) return;
  if (frames_written_ != layout_.frame_count)
    throw std::invalid_argument(
        file_problem(file_, std::to_string(frames_written_) + " frames written of the " +
                                std::to_string(layout_.frame_count) + " its header promises"));
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
