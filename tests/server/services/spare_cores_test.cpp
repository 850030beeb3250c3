// SpareCores: a pose borrows only cores that no job holds or waits for, a loan returns its cores
// when it ends, and the work queue holds a core for every job from post() until it has run, so
// that a large pose splits itself only while the daemon is otherwise idle.
#include "server/services/spare_cores.h"

#include <gtest/gtest.h>

#include <asio/thread_pool.hpp>
#include <future>

#include "server/transport/fair_work_queue.h"

namespace sweepd::server {
namespace {

TEST(SpareCores, LoansGrantOnlyWhatNoJobHoldsAndReturnWhenTheyEnd) {
  SpareCores cores(4);
  cores.job_queued();  // the job that asks for the loan holds its own core
  {
    const SpareCores::Loan loan = cores.borrow(8);
    EXPECT_EQ(3, loan.count());  // asked for 8, three were spare
    EXPECT_EQ(0, cores.spare());
    EXPECT_EQ(0, cores.borrow(1).count());  // nothing left for a second pose
    cores.job_queued();                     // another connection's job still queues
    EXPECT_EQ(-1, cores.spare());
    cores.job_done();
  }
  EXPECT_EQ(3, cores.spare());  // the loan came back
  EXPECT_EQ(0, cores.borrow(0).count());
  EXPECT_EQ(0, cores.borrow(-2).count());  // a pose too small to split asks for none
  cores.job_done();
  EXPECT_EQ(4, cores.spare());
}

TEST(SpareCores, TheWorkQueueHoldsACoreFromPostUntilTheJobHasRun) {
  asio::thread_pool pool(1);
  SpareCores cores(2);
  FairWorkQueue queue(pool, FairWorkQueue::steady_nanoseconds, {}, &cores);
  FairShare share;
  std::promise<void> both_posted, release;
  std::promise<int> seen_while_running;
  queue.post(share, [&] {
    both_posted.get_future().wait();
    seen_while_running.set_value(cores.spare());
    release.get_future().wait();
  });
  queue.post(share, [] {});  // queued behind the first: it holds the second core
  both_posted.set_value();
  EXPECT_EQ(0, seen_while_running.get_future().get());
  EXPECT_EQ(0, cores.borrow(1).count());
  release.set_value();
  pool.join();
  EXPECT_EQ(2, cores.spare());  // both jobs ran and gave their cores back
}

}  // namespace
}  // namespace sweepd::server
