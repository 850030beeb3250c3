// Tests for io::join_point_caches: shards of one range joined (given in any order) are the
// cache written whole, byte for byte, in PC2 and MDD; gaps, overlaps, other point counts, other
// formats and broken inputs are refused naming the files, and leave no output behind.
#include "io/point_cache/point_cache_join.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "io/files/file_bytes.h"
#include "io/point_cache/point_cache_save.h"
#include "tests/scratch_directory.h"

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;

// Frame f of a 3-point body: distinct exact floats per frame, point and axis.
std::vector<glm::vec3> frame_points(int f, int points = 3) {
  std::vector<glm::vec3> frame;
  for (int p = 0; p < points; ++p) frame.emplace_back(p + 0.5f, f * 0.25f, -(f + p) * 0.125f);
  return frame;
}

// Frames first..last of the body as a cache at 24 fps.
fs::path write_frames(const fs::path& file, int first, int last, int points = 3) {
  PointCacheWriter writer(file, {.format = *point_cache_format(file),
                                 .point_count = points,
                                 .frame_count = last - first + 1,
                                 .first_frame = first,
                                 .frames_per_second = 24.0});
  for (int f = first; f <= last; ++f) writer.write_frame(frame_points(f, points));
  writer.finish();
  return file;
}

TEST(PointCacheJoin, ShardsInAnyOrderJoinToTheWholeCacheByteForByte) {
  test::ScratchDirectory dir("join");
  for (const std::string extension : {".pc2", ".mdd"}) {
    const fs::path whole = write_frames(dir.path() / ("whole" + extension), 5, 14);
    const std::vector<fs::path> shards = {write_frames(dir.path() / ("c" + extension), 11, 14),
                                          write_frames(dir.path() / ("a" + extension), 5, 7),
                                          write_frames(dir.path() / ("b" + extension), 8, 10)};
    const fs::path joined = dir.path() / ("joined" + extension);
    const JoinedPointCache result = join_point_caches(shards, joined);
    EXPECT_EQ(result.inputs, 3);
    EXPECT_EQ(result.header.frame_count, 10);
    EXPECT_EQ(read_file_bytes(joined), read_file_bytes(whole)) << extension;
  }
}

void expect_refusal(const std::function<void()>& run, const std::vector<std::string>& parts) {
  try {
    run();
    ADD_FAILURE() << "no exception; expected: " << parts.front();
  } catch (const std::exception& e) {
    const std::string message = e.what();
    for (const std::string& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << message << "\nlacks: " << part;
  }
}

TEST(PointCacheJoin, RefusesWhatDoesNotJoinNamingTheFiles) {
  test::ScratchDirectory dir("join_refusals");
  const fs::path d = dir.path();
  const fs::path a = write_frames(d / "a.pc2", 0, 4), b = write_frames(d / "b.pc2", 6, 9);
  const fs::path c = write_frames(d / "c.pc2", 3, 9), wide = write_frames(d / "w.pc2", 5, 9, 4);
  const fs::path m = write_frames(d / "m.mdd", 5, 9), m1 = write_frames(d / "m1.mdd", 0, 0);
  const fs::path m2 = write_frames(d / "m2.mdd", 2, 2), gap = write_frames(d / "g.mdd", 11, 12);
  const fs::path out = d / "out.pc2";
  expect_refusal(
      [&] {
        join_point_caches({a, b}, out);
      },
      {"non-contiguous caches", "a.pc2 (frames 0-4) then", "b.pc2 (frames 6-9)"});
  expect_refusal(
      [&] {
        join_point_caches({c, a}, out);
      },
      {"overlapping caches", "a.pc2 (frames 0-4) then", "c.pc2 (frames 3-9)"});
  expect_refusal(
      [&] {
        join_point_caches({a, wide}, out);
      },
      {"point counts differ", "a.pc2 has 3", "w.pc2 4"});
  expect_refusal([&] { join_point_caches({a, m}, out); }, {"m.mdd is MDD", "out.pc2 not"});
  expect_refusal(
      [&] {
        join_point_caches({m, gap}, d / "out.mdd");
      },
      {"non-contiguous caches", "m.mdd (times", "g.mdd (times"});
  expect_refusal(
      [&] {
        join_point_caches({m1, m2}, d / "out.mdd");
      },
      {"MDD caches of one frame each carry no frame interval"});
  expect_refusal([&] { join_point_caches({a}, d / "out.abc"); }, {"out.abc", ".pc2 or .mdd"});
  expect_refusal([&] { join_point_caches({a, a}, a); }, {"a.pc2 is also an input"});
  fs::resize_file(b, 40);
  expect_refusal([&] { join_point_caches({a, b}, out); }, {"b.pc2", "truncated"});
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(d / "out.mdd"));
  EXPECT_FALSE(fs::exists(d / "out.pc2.partial")) << "no partial file left behind";
}

}  // namespace
}  // namespace sweepd::io
