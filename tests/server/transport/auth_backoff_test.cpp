// How wrong tokens are slowed per address (server/transport/auth_backoff.h): free failures,
// then a wait that doubles to a cap, Hellos refused unchecked meanwhile, and each burst
// reported once with its counts when it has been quiet long enough. Time is the test's own
// clock (time points passed in), so nothing here depends on how fast the machine is.
#include "server/transport/auth_backoff.h"

#include <gtest/gtest.h>

namespace sweepd::server {
namespace {

using std::chrono::milliseconds;
using Clock = AuthBackoff::Clock;

TEST(AuthBackoff, FreeFailuresThenAWaitThatDoublesToTheCap) {
  AuthBackoff backoff(/*free_failures=*/2, milliseconds(100), milliseconds(350));
  const Clock::time_point t0 = Clock::now();
  EXPECT_TRUE(backoff.failed("a", t0));   // starts the burst
  EXPECT_FALSE(backoff.failed("a", t0));  // the second free failure
  EXPECT_EQ(backoff.wait("a", t0), milliseconds(0));
  backoff.failed("a", t0);  // third: 100 ms
  EXPECT_EQ(backoff.wait("a", t0), milliseconds(100));
  EXPECT_EQ(backoff.wait("a", t0 + milliseconds(60)), milliseconds(40));
  EXPECT_EQ(backoff.wait("a", t0 + milliseconds(100)), milliseconds(0));
  backoff.failed("a", t0 + milliseconds(100));  // fourth: 200 ms
  EXPECT_EQ(backoff.wait("a", t0 + milliseconds(100)), milliseconds(200));
  backoff.failed("a", t0 + milliseconds(300));  // fifth: 400 ms, capped at 350
  EXPECT_EQ(backoff.wait("a", t0 + milliseconds(300)), milliseconds(350));
  // Other addresses are not slowed by "a".
  EXPECT_EQ(backoff.wait("b", t0 + milliseconds(300)), milliseconds(0));
  // Hundreds of failures neither overflow the doubling nor pass the cap.
  for (int i = 0; i < 300; ++i) backoff.failed("a", t0 + milliseconds(400));
  EXPECT_EQ(backoff.wait("a", t0 + milliseconds(400)), milliseconds(350));
}

TEST(AuthBackoff, ABurstIsReportedOnceWithItsCountsWhenQuiet) {
  AuthBackoff backoff(/*free_failures=*/1, milliseconds(100), milliseconds(1000));
  const Clock::time_point t0 = Clock::now();
  backoff.failed("a", t0);
  backoff.failed("a", t0 + milliseconds(10));  // waits 100 ms
  EXPECT_GT(backoff.wait("a", t0 + milliseconds(20)).count(), 0);
  EXPECT_GT(backoff.wait("a", t0 + milliseconds(30)).count(), 0);
  // Not quiet 999 ms after its last event; quiet at 1000.
  EXPECT_TRUE(backoff.end_quiet_bursts(t0 + milliseconds(1029)).empty());
  const std::vector<AuthBackoff::Burst> ended = backoff.end_quiet_bursts(t0 + milliseconds(1030));
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0].address, "a");
  EXPECT_EQ(ended[0].failures, 2u);
  EXPECT_EQ(ended[0].refused, 2u);
  EXPECT_TRUE(backoff.end_quiet_bursts(t0 + milliseconds(5000)).empty());
  // Forgotten: the address starts afresh with its free failures.
  EXPECT_TRUE(backoff.failed("a", t0 + milliseconds(5000)));
  EXPECT_EQ(backoff.wait("a", t0 + milliseconds(5000)), milliseconds(0));
}

TEST(AuthBackoff, PastTheAddressBoundTheQuietestBurstEndsToMakeRoom) {
  AuthBackoff backoff(/*free_failures=*/0, milliseconds(100), milliseconds(1000),
                      /*max_addresses=*/2);
  const Clock::time_point t0 = Clock::now();
  backoff.failed("a", t0);
  backoff.failed("b", t0 + milliseconds(1));
  backoff.failed("c", t0 + milliseconds(2));
  const std::vector<AuthBackoff::Burst> ended = backoff.end_quiet_bursts(t0 + milliseconds(3));
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0].address, "a");
  EXPECT_GT(backoff.wait("c", t0 + milliseconds(3)).count(), 0);
}

}  // namespace
}  // namespace sweepd::server
