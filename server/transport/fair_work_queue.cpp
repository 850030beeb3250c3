#include "server/transport/fair_work_queue.h"

#include <algorithm>
#include <asio/post.hpp>
#include <chrono>

namespace sweepd::server {

FairWorkQueue::FairWorkQueue(asio::thread_pool& pool, Clock clock)
    : pool_(pool), clock_(std::move(clock)) {}

std::uint64_t FairWorkQueue::steady_nanoseconds() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::steady_clock::now().time_since_epoch())
                                        .count());
}

void FairWorkQueue::post(FairShare& share, std::function<void()> job) {
  {
    const std::lock_guard lock(mutex_);
    const std::uint64_t tag = std::max(virtual_time_, share.next_tag);
    // Until this job is charged, the connection's next one queues one last cost behind it
    // (at least a nanosecond, so that its own jobs keep their order).
    share.next_tag = tag + std::max<std::uint64_t>(share.last_cost, 1);
    jobs_.emplace(std::pair{tag, arrivals_++}, Job{&share, std::move(job)});
  }
  asio::post(pool_, [this] { run_one(); });
}

void FairWorkQueue::run_one() {
  Job job;
  std::uint64_t tag = 0;
  {
    const std::lock_guard lock(mutex_);
    auto first = jobs_.begin();  // never empty: one token per job
    tag = first->first.first;
    virtual_time_ = std::max(virtual_time_, tag);
    job = std::move(first->second);
    jobs_.erase(first);
  }
  const std::uint64_t start = clock_();
  job.run();
  const std::uint64_t cost = clock_() - start;
  const std::lock_guard lock(mutex_);  // before `job` (which may own the share) is destroyed
  job.share->last_cost = cost;
  job.share->next_tag = std::max(job.share->next_tag, tag + cost);
}

}  // namespace sweepd::server
