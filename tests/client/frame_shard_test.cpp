// FrameShard: N shards of a range own every frame exactly once, in contiguous slices whose
// sizes differ by at most one; "I/N" and the Indexed Job's variables are read strictly.
#include "client/frame_shard.h"

#include <gtest/gtest.h>

#include <map>

namespace sweepd::client {
namespace {

TEST(FrameShard, ShardsCoverTheRangeOnceInBalancedContiguousSlices) {
  for (const console::FrameRange range :
       {console::FrameRange{0, 0}, console::FrameRange{300, 305}, console::FrameRange{7, 106},
        console::FrameRange{0, 2408}}) {
    for (int count = 1; count <= 12; ++count) {
      SCOPED_TRACE(std::to_string(range.first) + "-" + std::to_string(range.last) + " in " +
                   std::to_string(count));
      int next = range.first, smallest = range.count(), largest = 0, empty = 0;
      for (int index = 0; index < count; ++index) {
        const std::optional<console::FrameRange> slice = shard_frames(range, {index, count});
        if (!slice) {
          ++empty;
          smallest = 0;
          continue;
        }
        EXPECT_EQ(slice->first, next) << "contiguous, in index order, no frame twice";
        next = slice->last + 1;
        smallest = std::min(smallest, slice->count());
        largest = std::max(largest, slice->count());
      }
      EXPECT_EQ(next, range.last + 1) << "no frame left out";
      EXPECT_LE(largest - smallest, 1);
      EXPECT_EQ(empty, std::max(0, count - range.count())) << "only surplus shards are empty";
    }
  }
}

TEST(FrameShard, ParsesIndexOverCountOnly) {
  const std::optional<FrameShard> shard = parse_frame_shard("3/8");
  ASSERT_TRUE(shard);
  EXPECT_EQ(shard->index, 3);
  EXPECT_EQ(shard->count, 8);
  for (const char* bad : {"", "3", "8/8", "9/8", "1/0", "-1/2", "1/-2", "+1/2", "1/2x", " 1/2",
                          "1//2", "a/b", "1/2/3"})
    EXPECT_FALSE(parse_frame_shard(bad)) << bad;
}

TEST(FrameShard, ReadsAnIndexedJobsVariables) {
  std::map<std::string, std::string> variables;
  const auto get = [&variables](const char* name) -> std::optional<std::string> {
    const auto found = variables.find(name);
    if (found == variables.end()) return std::nullopt;
    return found->second;
  };
  EXPECT_FALSE(frame_shard_from_environment(get)) << "neither set: the whole range";

  variables = {{"JOB_COMPLETION_INDEX", "2"}, {"JOB_COMPLETIONS", "4"}};
  const std::optional<FrameShard> shard = frame_shard_from_environment(get);
  ASSERT_TRUE(shard);
  EXPECT_EQ(shard->index, 2);
  EXPECT_EQ(shard->count, 4);

  auto problem = [&]() -> std::string {
    try {
      frame_shard_from_environment(get);
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "";
  };
  variables = {{"JOB_COMPLETION_INDEX", "2"}};
  EXPECT_NE(problem().find("JOB_COMPLETIONS is not"), std::string::npos) << problem();
  variables = {{"JOB_COMPLETIONS", "4"}};
  EXPECT_NE(problem().find("JOB_COMPLETION_INDEX is not"), std::string::npos) << problem();
  variables = {{"JOB_COMPLETION_INDEX", "4"}, {"JOB_COMPLETIONS", "4"}};
  EXPECT_NE(problem().find("JOB_COMPLETION_INDEX=4 JOB_COMPLETIONS=4"), std::string::npos)
      << problem();
}

}  // namespace
}  // namespace sweepd::client
