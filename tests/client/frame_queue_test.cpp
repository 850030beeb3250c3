// FrameQueue: frames go out in order, a retried frame goes back to the front until its
// attempts are spent, the last thread to give up fails what waits, and under threads that
// retry at random every frame still ends exactly once.
#include "client/frame_queue.h"

#include <gtest/gtest.h>

#include <atomic>
#include <numeric>
#include <random>
#include <thread>

namespace sweepd::client {
namespace {

TEST(FrameQueue, RetriedFramesGoBackToTheFrontUntilTheirAttemptsAreSpent) {
  FrameQueue queue({10, 11, 12}, /*max_attempts=*/2, /*threads=*/1);
  EXPECT_EQ(queue.take(false), 10);
  EXPECT_EQ(queue.take(false), 11);
  queue.retry(11, "lost");
  queue.retry(10, "lost");  // given back in reverse, they go out in order again
  EXPECT_EQ(queue.take(false), 10);
  EXPECT_EQ(queue.take(false), 11);
  queue.rendered(10);
  queue.retry(11, "lost again");  // its second attempt: it fails
  EXPECT_EQ(queue.take(false), 12);
  EXPECT_EQ(queue.take(false), std::nullopt);
  EXPECT_FALSE(queue.ended());
  queue.fail(12, "invalid pose");
  EXPECT_TRUE(queue.ended());
  EXPECT_EQ(queue.take(true), std::nullopt) << "an ended queue does not block";
  const FrameQueue::Tally tally = queue.tally();
  EXPECT_EQ(tally.rendered, 1);
  EXPECT_EQ(tally.retried, 2);
  EXPECT_EQ(tally.failed, 2);
  EXPECT_EQ(tally.failures.at(11), "lost again (after 2 attempts)");
  EXPECT_EQ(tally.failures.at(12), "invalid pose");
}

TEST(FrameQueue, TheLastThreadToGiveUpFailsWhatWaits) {
  FrameQueue queue({1, 2, 3}, 3, /*threads=*/2);
  EXPECT_EQ(queue.take(false), 1);
  queue.retry(1, "server gone");
  queue.retire("a: refused");  // one thread is left: the frames wait for it
  EXPECT_FALSE(queue.ended());
  EXPECT_EQ(queue.tally().failed, 0);
  queue.retire("b: unreachable");
  EXPECT_TRUE(queue.ended());
  const FrameQueue::Tally tally = queue.tally();
  EXPECT_EQ(tally.failed, 3);
  EXPECT_EQ(tally.failures.at(2), "b: unreachable");
}

TEST(FrameQueue, AWaitingThreadWakesForARetriedFrame) {
  FrameQueue queue({5}, 3, 2);
  ASSERT_EQ(queue.take(false), 5);
  std::optional<int> taken;
  std::thread waiter([&] { taken = queue.take(true); });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the waiter is (likely) blocked
  queue.retry(5, "timed out");
  waiter.join();
  EXPECT_EQ(taken, 5);
}

TEST(FrameQueue, UnderRandomRetriesEveryFrameEndsExactlyOnce) {
  constexpr int kFrames = 2000, kThreads = 4;
  std::vector<int> frames(kFrames);
  std::iota(frames.begin(), frames.end(), 0);
  FrameQueue queue(frames, /*max_attempts=*/4, kThreads);
  std::vector<std::atomic<int>> rendered(kFrames);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      std::mt19937 random(t);
      while (const std::optional<int> frame = queue.take(true)) {
        if (random() % 3 == 0) {
          queue.retry(*frame, "unlucky");  // a third of all attempts fail
        } else {
          ++rendered[*frame];
          queue.rendered(*frame);
        }
      }
      queue.retire("");
    });
  }
  for (std::thread& thread : threads) thread.join();
  const FrameQueue::Tally tally = queue.tally();
  EXPECT_EQ(tally.rendered + tally.failed, kFrames);
  for (int frame = 0; frame < kFrames; ++frame) {
    EXPECT_EQ(rendered[frame] + static_cast<int>(tally.failures.count(frame)), 1)
        << "frame " << frame;
  }
  // 1/3 per attempt over 4 attempts: about kFrames / 81 = 25 fail; a wide bound, only to show
  // that retries and failures both happened.
  EXPECT_GT(tally.failed, 0);
  EXPECT_LT(tally.failed, 100);
  EXPECT_GT(tally.retried, kFrames / 4);
}

}  // namespace
}  // namespace sweepd::client
