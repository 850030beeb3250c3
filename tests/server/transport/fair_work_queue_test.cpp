// FairWorkQueue: a connection that arrives behind another's backlog runs next, busy connections
// take turns, each connection's own jobs keep their order, and a job is charged the worker time
// it took. One worker thread, held by a first job until every job is queued, so the order is
// the queue's alone; the queue's clock is the test's, moved by the jobs (1 unless a test says).
#include "server/transport/fair_work_queue.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <future>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace sweepd::server {
namespace {

class FairWorkQueueTest : public ::testing::Test {
 protected:
  // Queues a job that holds the one worker until release().
  void hold_worker() {
    queue_.post(holder_, [this] { release_.get_future().wait(); });
  }
  void release() {
    release_.set_value();
    pool_.join();
  }
  // A job that records its name, takes `cost` on the test's clock, then runs `then`.
  void post(FairShare& share, std::string name, std::uint64_t cost = 1,
            std::function<void()> then = {}) {
    queue_.post(share, [this, name, cost, then] {
      {
        const std::lock_guard lock(mutex_);
        order_.push_back(name);
      }
      now_ += cost;
      if (then) then();
    });
  }

  std::size_t ran() {
    const std::lock_guard lock(mutex_);
    return order_.size();
  }

  asio::thread_pool pool_{1};
  std::atomic<std::uint64_t> now_{0};
  FairWorkQueue queue_{pool_, [this] { return now_.load(); }};
  FairShare holder_;
  std::promise<void> release_;
  std::mutex mutex_;
  std::vector<std::string> order_;
};

TEST_F(FairWorkQueueTest, ANewConnectionRunsBeforeAnotherConnectionsBacklog) {
  hold_worker();
  FairShare streaming, fresh;
  for (int i = 0; i < 10; ++i) post(streaming, "a" + std::to_string(i));
  post(fresh, "new");
  release();
  // FIFO would run it 11th; fair queuing ties it with the backlog's first job (same tag, later
  // arrival), so it runs second.
  const std::vector<std::string> expected = {"a0", "new", "a1", "a2", "a3", "a4",
                                             "a5", "a6",  "a7", "a8", "a9"};
  EXPECT_EQ(order_, expected);
}

TEST_F(FairWorkQueueTest, BusyConnectionsTakeTurnsInTheirOwnOrder) {
  hold_worker();
  FairShare a, b, c;
  for (int i = 0; i < 3; ++i) post(a, "a" + std::to_string(i));
  for (int i = 0; i < 3; ++i) post(b, "b" + std::to_string(i));
  post(c, "c0");
  release();
  const std::vector<std::string> expected = {"a0", "b0", "c0", "a1", "b1", "a2", "b2"};
  EXPECT_EQ(order_, expected);
}

TEST_F(FairWorkQueueTest, AConnectionIdleForLongStartsAtTheVirtualTimeNotBehindIt) {
  // `early` ran long ago; `busy` has run five since. When both queue again, `early` gets no
  // credit for its idle time beyond starting at the current turn: it goes first, then they
  // alternate.
  FairShare early, busy;
  post(early, "e0");
  for (int i = 0; i < 5; ++i) post(busy, "x" + std::to_string(i));
  while (ran() < 6) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  hold_worker();  // starts at the virtual time, x4's turn
  for (int i = 0; i < 3; ++i) post(busy, "y" + std::to_string(i));
  for (int i = 1; i < 4; ++i) post(early, "e" + std::to_string(i));
  release();
  const std::vector<std::string> expected = {"e0", "x0", "x1", "x2", "x3", "x4",
                                             "e1", "y0", "e2", "y1", "e3", "y2"};
  EXPECT_EQ(order_, expected);
}

TEST_F(FairWorkQueueTest, ACheapJobCostsItsConnectionLittle) {
  // `a` and `b` have each used 10 units; `fresh` loads a model already loaded (0 units) and then
  // asks for its first pose. Charged by the job, each of a and b would have used one turn like
  // fresh's load, and the pose would queue behind both of their next jobs; charged by the time
  // taken, it runs first.
  FairShare a, b, fresh;
  post(a, "a0", 10);
  post(b, "b0", 10);
  while (ran() < 2) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  hold_worker();
  post(a, "a1", 10);
  post(b, "b1", 10);
  post(fresh, "load", 0, [this, &fresh] { post(fresh, "pose", 10); });
  release();
  const std::vector<std::string> expected = {"a0", "b0", "load", "pose", "a1", "b1"};
  EXPECT_EQ(order_, expected);
}

// A worker that spins (FairWorkQueue's `spin`) runs a job posted while it polls itself, before
// anything the pool queued after that job's token; without a spin the pool's own order holds.
// One pool thread, so the order says who ran the job: a job run from its own token would run
// after the marker posted to the pool before it.
std::vector<std::string> order_after_a_finished_job(std::chrono::microseconds spin) {
  asio::thread_pool pool(1);
  FairWorkQueue queue(pool, FairWorkQueue::steady_nanoseconds, spin);
  FairShare share;
  std::mutex mutex;
  std::vector<std::string> order;
  const auto record = [&](const char* name) {
    const std::lock_guard lock(mutex);
    order.emplace_back(name);
  };
  std::promise<void> first_done;
  queue.post(share, [&] {
    record("first");
    first_done.set_value();
  });
  first_done.get_future().wait();  // the worker is still in the first job's token
  asio::post(pool, [&] { record("marker"); });
  queue.post(share, [&] { record("second"); });
  pool.join();
  return order;
}

TEST(FairWorkQueueSpin, ASpinningWorkerRunsTheNextJobWithoutSleeping) {
  // The spin (1 s) only has to outlast the two posts after the first job ends; the test then
  // waits it out once more after the second job.
  const std::vector<std::string> spun = {"first", "second", "marker"};
  EXPECT_EQ(order_after_a_finished_job(std::chrono::seconds(1)), spun);
  const std::vector<std::string> slept = {"first", "marker", "second"};
  EXPECT_EQ(order_after_a_finished_job(std::chrono::microseconds(0)), slept);
}

TEST(FairWorkQueueSpin, EveryJobRunsOnceWhileWorkersSpin) {
  // Two workers, both finding jobs while they spin and tokens whose job was already taken:
  // 4 threads post 500 jobs each; every one runs exactly once and the pool ends.
  asio::thread_pool pool(2);
  FairWorkQueue queue(pool, FairWorkQueue::steady_nanoseconds, std::chrono::microseconds(200));
  constexpr int kPosters = 4, kJobs = 500;
  std::vector<std::atomic<int>> runs(kPosters * kJobs);
  std::vector<FairShare> shares(kPosters);
  std::vector<std::thread> posters;
  for (int p = 0; p < kPosters; ++p) {
    posters.emplace_back([&, p] {
      for (int j = 0; j < kJobs; ++j) {
        queue.post(shares[p], [&runs, index = p * kJobs + j] { runs[index].fetch_add(1); });
        if (j % 50 == 0) std::this_thread::sleep_for(std::chrono::microseconds(300));
      }
    });
  }
  for (std::thread& poster : posters) poster.join();
  pool.join();
  int not_once = 0;
  for (const std::atomic<int>& count : runs) not_once += count.load() != 1;
  EXPECT_EQ(not_once, 0);
}

}  // namespace
}  // namespace sweepd::server
