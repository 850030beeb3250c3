// Which unauthenticated connections are shed (server/transport/stranger_slots.h): past an
// address's quota its own oldest goes, past the total the oldest of the address holding most,
// never the newcomer; those that authenticated or closed free their slot.
#include "server/transport/stranger_slots.h"

#include <gtest/gtest.h>

#include <set>

namespace sweepd::server {
namespace {

using Shed = StrangerSlots::Shed;

std::vector<std::uint64_t> ids(const std::vector<Shed>& shed) {
  std::vector<std::uint64_t> out;
  for (const Shed& s : shed) out.push_back(s.id);
  return out;
}

TEST(StrangerSlots, PastTheAddressQuotaItsOwnOldestIsShed) {
  StrangerSlots slots(/*total=*/10, /*per_address=*/3);
  EXPECT_TRUE(slots.admit(1, "10.0.0.1").empty());
  EXPECT_TRUE(slots.admit(2, "10.0.0.2").empty());
  EXPECT_TRUE(slots.admit(3, "10.0.0.1").empty());
  EXPECT_TRUE(slots.admit(4, "10.0.0.1").empty());
  const std::vector<Shed> shed = slots.admit(5, "10.0.0.1");
  ASSERT_EQ(shed.size(), 1u);
  EXPECT_EQ(shed[0].id, 1u);  // the oldest of 10.0.0.1, not 10.0.0.2's older one
  EXPECT_TRUE(shed[0].address_full);
  EXPECT_EQ(slots.held_by("10.0.0.1"), 3u);
  EXPECT_EQ(slots.held_by("10.0.0.2"), 1u);
  EXPECT_EQ(ids(slots.admit(6, "10.0.0.1")), std::vector<std::uint64_t>{3});
}

TEST(StrangerSlots, PastTheTotalTheCrowdingAddressPaysAndTheNewcomerStays) {
  StrangerSlots slots(/*total=*/4, /*per_address=*/4);
  EXPECT_TRUE(slots.admit(1, "a").empty());
  EXPECT_TRUE(slots.admit(2, "b").empty());
  EXPECT_TRUE(slots.admit(3, "b").empty());
  EXPECT_TRUE(slots.admit(4, "b").empty());
  // "a" is older, but "b" holds three of the four.
  const std::vector<Shed> shed = slots.admit(5, "a");
  ASSERT_EQ(shed.size(), 1u);
  EXPECT_EQ(shed[0].id, 2u);
  EXPECT_FALSE(shed[0].address_full);
  EXPECT_EQ(slots.size(), 4u);
  // A stream of newcomers from one address sheds only older strangers, never itself.
  std::set<std::uint64_t> shed_ids;
  for (std::uint64_t id = 6; id < 40; ++id) {
    for (const Shed& s : slots.admit(id, "c")) {
      EXPECT_LT(s.id, id);
      shed_ids.insert(s.id);
    }
    EXPECT_EQ(slots.size(), 4u);
  }
  EXPECT_EQ(shed_ids.count(39), 0u);
}

TEST(StrangerSlots, ThoseThatLeaveFreeTheirSlots) {
  StrangerSlots slots(/*total=*/2, /*per_address=*/2);
  EXPECT_TRUE(slots.admit(1, "a").empty());
  EXPECT_TRUE(slots.admit(2, "a").empty());
  slots.forget([](std::uint64_t id) { return id != 1; });  // 1 authenticated
  EXPECT_EQ(slots.size(), 1u);
  EXPECT_TRUE(slots.admit(3, "a").empty());
  EXPECT_EQ(ids(slots.admit(4, "a")), std::vector<std::uint64_t>{2});
}

TEST(StrangerSlots, AQuotaLargerThanTheTotalIsTheTotal) {
  StrangerSlots slots(/*total=*/2, /*per_address=*/5);
  EXPECT_EQ(slots.per_address(), 2u);
  EXPECT_THROW(StrangerSlots(0, 1), std::invalid_argument);
}

}  // namespace
}  // namespace sweepd::server
