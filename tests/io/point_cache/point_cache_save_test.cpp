// Tests for io::PointCacheWriter: the bytes of PC2 and MDD files field by field against the
// formats (as Blender's MOD_meshcache_pc2.c / MOD_meshcache_mdd.c read them), a round trip
// through a small reader written from the formats (tests/io/point_cache_read.h), the Blender axes,
// and the refusals.
#include "io/point_cache/point_cache_save.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/files/file_bytes.h"
#include "tests/io/point_cache_read.h"
#include "tests/scratch_directory.h"

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;

// Three frames of two points; frame f's point p is (p + 0.5, f + 0.25, -(f + p) - 0.125), so
// a swapped frame, point or axis shows. Powers of two: exact in float32.
std::vector<std::vector<glm::vec3>> three_frames() {
  std::vector<std::vector<glm::vec3>> frames;
  for (int f = 0; f < 3; ++f)
    frames.push_back({{0.5f, f + 0.25f, -f - 0.125f}, {1.5f, f + 0.25f, -f - 1.125f}});
  return frames;
}

fs::path write_three_frames(const fs::path& file, PointCacheFormat format,
                            PointCacheAxes axes = PointCacheAxes::kGltf) {
  PointCacheWriter writer(file, {.format = format,
                                 .axes = axes,
                                 .point_count = 2,
                                 .frame_count = 3,
                                 .first_frame = 10,
                                 .frames_per_second = 120.0});
  for (const std::vector<glm::vec3>& frame : three_frames()) writer.write_frame(frame);
  writer.finish();
  return file;
}

TEST(PointCacheSave, Pc2HeaderAndAKnownVertexByteForByte) {
  test::ScratchDirectory dir("pc2_bytes");
  const std::vector<std::uint8_t> bytes =
      read_file_bytes(write_three_frames(dir.path() / "m.pc2", PointCacheFormat::kPc2));
  ASSERT_EQ(bytes.size(), 32u + 3 * 2 * 12) << "32-byte header, 3 samples of 2 points";
  EXPECT_EQ(std::memcmp(bytes.data(), "POINTCACHE2\0", 12), 0) << "signature with its zero";
  const std::vector<std::uint8_t> version(bytes.begin() + 12, bytes.begin() + 16);
  EXPECT_EQ(version, (std::vector<std::uint8_t>{1, 0, 0, 0})) << "int32 1, little-endian";
  EXPECT_EQ(test::cache_field(bytes, 16, true), 2u) << "point count";
  EXPECT_EQ(test::cache_float(bytes, 20, true), 10.0f) << "start frame: the first frame written";
  EXPECT_EQ(test::cache_float(bytes, 24, true), 1.0f) << "sampling: a sample every frame";
  EXPECT_EQ(test::cache_field(bytes, 28, true), 3u) << "sample count";
  // Sample 2, point 1: (1.5, 2.25, -3.125); 1.5f is 0x3fc00000, low byte first.
  const std::size_t at = 32 + (2 * 2 + 1) * 12;
  const std::vector<std::uint8_t> x(bytes.begin() + at, bytes.begin() + at + 4);
  EXPECT_EQ(x, (std::vector<std::uint8_t>{0x00, 0x00, 0xc0, 0x3f}));
  EXPECT_EQ(test::cache_float(bytes, at + 4, true), 2.25f);
  EXPECT_EQ(test::cache_float(bytes, at + 8, true), -3.125f);
}

TEST(PointCacheSave, MddHeaderTimesAndAKnownVertexBigEndian) {
  test::ScratchDirectory dir("mdd_bytes");
  const std::vector<std::uint8_t> bytes =
      read_file_bytes(write_three_frames(dir.path() / "m.mdd", PointCacheFormat::kMdd));
  ASSERT_EQ(bytes.size(), 8u + 3 * 4 + 3 * 2 * 12) << "counts, a time per frame, 3 frames";
  const std::vector<std::uint8_t> frames(bytes.begin(), bytes.begin() + 4);
  EXPECT_EQ(frames, (std::vector<std::uint8_t>{0, 0, 0, 3})) << "int32 3, big-endian";
  EXPECT_EQ(test::cache_field(bytes, 4, false), 2u) << "point count";
  // Frames 10, 11, 12 of a 120 fps clip: their seconds, rounded to float32 (1e-7 s).
  for (int f = 0; f < 3; ++f)
    EXPECT_NEAR(test::cache_float(bytes, 8 + 4 * f, false), (10 + f) / 120.0, 1e-7) << "time " << f;
  // Frame 2, point 1: (1.5, 2.25, -3.125); 1.5f is 0x3fc00000, high byte first.
  const std::size_t at = 20 + (2 * 2 + 1) * 12;
  const std::vector<std::uint8_t> x(bytes.begin() + at, bytes.begin() + at + 4);
  EXPECT_EQ(x, (std::vector<std::uint8_t>{0x3f, 0xc0, 0x00, 0x00}));
  EXPECT_EQ(test::cache_float(bytes, at + 4, false), 2.25f);
  EXPECT_EQ(test::cache_float(bytes, at + 8, false), -3.125f);
}

// Float32 in, float32 out: the reader must give back the very numbers (no tolerance).
TEST(PointCacheSave, BothFormatsReadBackToTheFramesWritten) {
  test::ScratchDirectory dir("round_trip");
  for (const auto& [name, format] :
       {std::pair{"m.pc2", PointCacheFormat::kPc2}, std::pair{"m.mdd", PointCacheFormat::kMdd}}) {
    const test::PointCache cache =
        test::read_point_cache(write_three_frames(dir.path() / name, format));
    ASSERT_EQ(cache.frames, 3) << name;
    ASSERT_EQ(cache.points, 2) << name;
    const std::vector<std::vector<glm::vec3>> frames = three_frames();
    for (int f = 0; f < 3; ++f)
      for (int p = 0; p < 2; ++p)
        EXPECT_EQ(cache.positions[f * 2 + p], frames[f][p])
            << name << " frame " << f << " point " << p;
  }
}

// Blender's glTF importer turns glTF's +Y up into Blender's +Z up: (x, y, z) -> (x, -z, y).
TEST(PointCacheSave, BlenderAxesPutGltfUpOnZAndFrontOnMinusY) {
  test::ScratchDirectory dir("blender_axes");
  const test::PointCache cache = test::read_point_cache(
      write_three_frames(dir.path() / "m.pc2", PointCacheFormat::kPc2, PointCacheAxes::kBlender));
  ASSERT_EQ(cache.positions.size(), 6u);
  EXPECT_EQ(cache.positions[5], glm::vec3(1.5f, 3.125f, 2.25f)) << "(1.5, 2.25, -3.125) turned";
}

void expect_refusal(const std::function<void()>& run, const std::string& reason) {
  try {
    run();
    ADD_FAILURE() << "no exception; expected: " << reason;
  } catch (const std::exception& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("m.pc2"), std::string::npos) << message;
    EXPECT_NE(message.find(reason), std::string::npos) << message;
  }
}

// A render farm's frames arrive in any order: each lands at its own place, so the file is the
// one written in order byte for byte.
TEST(PointCacheSave, FramesWrittenOutOfOrderLandInTheirPlaces) {
  test::ScratchDirectory dir("out_of_order");
  for (const PointCacheFormat format : {PointCacheFormat::kPc2, PointCacheFormat::kMdd}) {
    const std::string extension = format == PointCacheFormat::kPc2 ? ".pc2" : ".mdd";
    const fs::path in_order = write_three_frames(dir.path() / ("a" + extension), format);
    const fs::path shuffled = dir.path() / ("b" + extension);
    PointCacheWriter writer(shuffled, {.format = format,
                                       .point_count = 2,
                                       .frame_count = 3,
                                       .first_frame = 10,
                                       .frames_per_second = 120.0});
    for (const int index : {2, 0, 1}) writer.write_frame_at(index, three_frames()[index]);
    writer.finish();
    EXPECT_EQ(read_file_bytes(shuffled), read_file_bytes(in_order)) << extension;
  }
}

// The header read back is the header written, and a file whose size is not what its header
// promises is refused naming the file and how.
TEST(PointCacheSave, HeaderReadBackAndTruncationRefused) {
  test::ScratchDirectory dir("header");
  const PointCacheHeader pc2 =
      read_point_cache_header(write_three_frames(dir.path() / "m.pc2", PointCacheFormat::kPc2));
  EXPECT_EQ(pc2.point_count, 2);
  EXPECT_EQ(pc2.frame_count, 3);
  EXPECT_EQ(pc2.start_frame, 10.0f);
  EXPECT_EQ(pc2.sampling, 1.0f);
  const PointCacheHeader mdd =
      read_point_cache_header(write_three_frames(dir.path() / "m.mdd", PointCacheFormat::kMdd));
  EXPECT_EQ(mdd.frame_count, 3);
  ASSERT_EQ(mdd.times.size(), 3u);
  EXPECT_EQ(mdd.times[2], static_cast<float>(12 / 120.0)) << "frame 12 at 120 fps";
  fs::resize_file(dir.path() / "m.pc2", 32 + 2 * 24 + 5);
  expect_refusal([&] { read_point_cache_header(dir.path() / "m.pc2"); },
                 "85 bytes where its header promises 104 (3 frames of 2 points): truncated");
  const std::vector<std::uint8_t> junk(40, 7);
  {
    std::FILE* out = std::fopen((dir.path() / "m.pc2").c_str(), "wb");
    std::fwrite(junk.data(), 1, junk.size(), out);
    std::fclose(out);
  }
  expect_refusal([&] { read_point_cache_header(dir.path() / "m.pc2"); },
                 "not a PC2 file: it does not start with POINTCACHE2");
}

TEST(PointCacheSave, FormatFromTheExtension) {
  EXPECT_EQ(point_cache_format("a/b.pc2"), PointCacheFormat::kPc2);
  EXPECT_EQ(point_cache_format("b.MDD"), PointCacheFormat::kMdd);
  EXPECT_EQ(point_cache_format("b.glb"), std::nullopt);
  EXPECT_EQ(point_cache_format("pc2"), std::nullopt) << "a name without an extension";
}

TEST(PointCacheSave, RefusesBadLayoutsAndFramesAndLeavesNoFile) {
  test::ScratchDirectory dir("refusals");
  const fs::path file = dir.path() / "m.pc2";
  const PointCacheLayout layout{.point_count = 2, .frame_count = 2};
  const std::vector<glm::vec3> frame(2), short_frame(1);
  expect_refusal([&] { PointCacheWriter(file, {.point_count = 0, .frame_count = 2}); },
                 "no points");
  expect_refusal([&] { PointCacheWriter(file, {.point_count = 2, .frame_count = 0}); },
                 "no frames");
  expect_refusal(
      [&] { PointCacheWriter(file, {.point_count = 2, .frame_count = 1, .frames_per_second = 0}); },
      "frame rate");
  expect_refusal([&] { PointCacheWriter(file, layout).write_frame(short_frame); },
                 "frame 0 has 1 points, the cache 2");
  expect_refusal(
      [&] {
        PointCacheWriter writer(file, layout);
        for (int i = 0; i < 3; ++i) writer.write_frame(frame);
      },
      "beyond the 2 promised");
  expect_refusal(
      [&] {
        PointCacheWriter writer(file, layout);
        writer.write_frame(frame);
        writer.finish();
      },
      "1 frames written of the 2");
  expect_refusal([&] { PointCacheWriter(file, layout).write_frame_at(2, frame); },
                 "frame index 2 outside the cache's 2");
  expect_refusal(
      [&] {
        PointCacheWriter writer(file, layout);
        writer.write_frame_at(1, frame);
        writer.write_frame_at(1, frame);
      },
      "frame index 1 written twice");
  expect_refusal([&] { PointCacheWriter(dir.path() / "missing" / "m.pc2", layout); },
                 "cannot create it");
  EXPECT_TRUE(fs::is_empty(dir.path())) << "no cache and no .partial file left behind";
}

}  // namespace
}  // namespace sweepd::io
