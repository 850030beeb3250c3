// Tests for motion::name_list: the names a warning or an error lists, capped.
#include "motion/name_list.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace sweepd::motion {
namespace {

TEST(NameListTest, ListsUpToTheCapThenCountsTheRest) {
  EXPECT_EQ(name_list(std::vector<std::string>{}), "");
  EXPECT_EQ(name_list(std::vector<std::string>{"Head"}), "Head");
  const std::vector<std::string> three = {"LThumb", "LeftFingerBase", "RThumb"};
  EXPECT_EQ(name_list(three), "LThumb, LeftFingerBase, RThumb");
  EXPECT_EQ(name_list(three, 3), "LThumb, LeftFingerBase, RThumb");  // exactly the cap: no "more"
  EXPECT_EQ(name_list(three, 1), "LThumb and 2 more");
  // A hand of 15 finger joints: the first 12 (kListedNames) and the count of the others.
  std::vector<std::string> fingers;
  for (int k = 1; k <= 15; ++k) fingers.push_back("Finger" + std::to_string(k));
  const std::string listed = name_list(fingers);
  EXPECT_TRUE(listed.starts_with("Finger1, Finger2, ")) << listed;
  EXPECT_TRUE(listed.ends_with("Finger12 and 3 more")) << listed;
  EXPECT_EQ(listed.find("Finger13"), std::string::npos) << listed;
}

}  // namespace
}  // namespace sweepd::motion
