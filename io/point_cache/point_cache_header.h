// PointCacheHeader: the header of a PC2 or MDD point cache (io/point_cache/point_cache_save.h has the
// layouts), encoded and read back, shared by the writer and the joiner (io/point_cache/point_cache_join.h).
//
// point_cache_format(file): the format a file's extension names (.pc2, .mdd, any case).
// point_cache_header_bytes(header): the header's bytes in the format's byte order.
// read_point_cache_header(file): a cache file's header, checked: the PC2 signature and version 1,
//   counts above 0, and a file size of exactly the header and the frames it promises.
//   Throws io::LoadError naming the file and the problem (unreadable, not a cache, truncated,
//   bytes past its frames).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace sweepd::io {

enum class PointCacheFormat { kPc2, kMdd };

std::optional<PointCacheFormat> point_cache_format(const std::filesystem::path& file);

struct PointCacheHeader {
  PointCacheFormat format = PointCacheFormat::kPc2;
  int point_count = 0;
  int frame_count = 0;
  float start_frame = 0.0f;  // PC2: the clip frame of sample 0
  float sampling = 1.0f;     // PC2: frames per sample
  std::vector<float> times;  // MDD: each frame's time in seconds (frame_count of them)

  std::uint64_t header_size() const;
  std::uint64_t frame_size() const { return std::uint64_t(point_count) * 12; }
  std::uint64_t file_size() const { return header_size() + frame_size() * frame_count; }
};

std::vector<std::uint8_t> point_cache_header_bytes(const PointCacheHeader& header);
PointCacheHeader read_point_cache_header(const std::filesystem::path& file);

}  // namespace sweepd::io
