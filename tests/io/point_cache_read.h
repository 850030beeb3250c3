// A small point cache reader for the tests, written from the formats as Blender's
// MOD_meshcache_pc2.c / MOD_meshcache_mdd.c read them (not from io/point_cache/point_cache_save.cpp), so a
// writer that misplaces a field or a byte fails to read back:
//   cache_field(bytes, offset, little)   a 32-bit field, little- or big-endian
//   read_point_cache(file)               a .pc2 (little-endian) or .mdd (big-endian) file's
//                                        header and frames; adds a test failure when the file's
//                                        size is not what its header promises
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <glm/glm.hpp>
#include <vector>

#include "io/files/file_bytes.h"

namespace sweepd::test {

inline std::uint32_t cache_field(const std::vector<std::uint8_t>& bytes, std::size_t offset,
                                 bool little) {
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i) {
    const std::uint32_t byte = bytes.at(offset + i);
    value |= byte << (little ? 8 * i : 8 * (3 - i));
  }
  return value;
}
inline float cache_float(const std::vector<std::uint8_t>& bytes, std::size_t offset,
                         bool little) {
  return std::bit_cast<float>(cache_field(bytes, offset, little));
}

struct PointCache {
  int frames = 0, points = 0;
  float start = 0.0f, sampling = 0.0f;  // PC2 only
  std::vector<float> times;             // MDD only: seconds per frame
  std::vector<glm::vec3> positions;     // frames × points, frame after frame
};

inline PointCache read_point_cache(const std::filesystem::path& file) {
  const std::vector<std::uint8_t> bytes = io::read_file_bytes(file);
  const bool pc2 = file.extension() == ".pc2";
  PointCache cache;
  std::size_t offset = 0;
  if (pc2) {
    cache.points = static_cast<int>(cache_field(bytes, 16, true));
    cache.start = cache_float(bytes, 20, true);
    cache.sampling = cache_float(bytes, 24, true);
    cache.frames = static_cast<int>(cache_field(bytes, 28, true));
    offset = 32;
  } else {
    cache.frames = static_cast<int>(cache_field(bytes, 0, false));
    cache.points = static_cast<int>(cache_field(bytes, 4, false));
    for (int f = 0; f < cache.frames; ++f)
      cache.times.push_back(cache_float(bytes, 8 + 4 * std::size_t(f), false));
    offset = 8 + 4 * std::size_t(cache.frames);
  }
  const std::size_t values = std::size_t(cache.frames) * std::size_t(cache.points);
  EXPECT_EQ(bytes.size(), offset + values * 12)
      << file << " holds exactly the frames its header promises";
  if (bytes.size() != offset + values * 12) return cache;
  for (std::size_t i = 0; i < values; ++i, offset += 12)
    cache.positions.emplace_back(cache_float(bytes, offset, pc2),
                                 cache_float(bytes, offset + 4, pc2),
                                 cache_float(bytes, offset + 8, pc2));
  return cache;
}

}  // namespace sweepd::test
