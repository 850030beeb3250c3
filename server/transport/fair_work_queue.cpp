#include "server/transport/fair_work_queue.h"

#include <algorithm>
#include <asio/post.hpp>
#include <chrono>
#include <thread>

namespace sweepd::server {

FairWorkQueue::FairWorkQueue(asio::thread_pool& pool, Clock clock, std::chrono::microseconds spin,
                             SpareCores* cores)
    : pool_(pool), clock_(std::move(clock)), cores_(cores), spin_(spin) {}

std::uint64_t FairWorkQueue::steady_nanoseconds() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::steady_clock::now().time_since_epoch())
                                        .count());
}

void FairWorkQueue::post(FairShare& share, std::function<void()> job) {
  if (cores_) cores_->job_queued();
  {
    const std::lock_guard lock(mutex_);
    const std::uint64_t tag = std::max(virtual_time_, share.next_tag);
    // Until this job is charged, the connection's next one queues one last cost behind it
    // (at least a nanosecond, so that its own jobs keep their order).
    share.next_tag = tag + std::max<std::uint64_t>(share.last_cost, 1);
    jobs_.emplace(std::pair{tag, arrivals_++}, Job{&share, std::move(job)});
    queued_.store(jobs_.size(), std::memory_order_release);
  }
  asio::post(pool_, [this] { run_one(); });
}

void FairWorkQueue::run_one() {
  while (run_next() && spin_.count() > 0 && spin_for_job()) {
  }
}

bool FairWorkQueue::run_next() {
  Job job;
  std::uint64_t tag = 0;
  {
    const std::lock_guard lock(mutex_);
    // Empty when a spinning worker took this token's job: tokens never number fewer than jobs.
    if (jobs_.empty()) return false;
    auto first = jobs_.begin();
    tag = first->first.first;
    virtual_time_ = std::max(virtual_time_, tag);
    job = std::move(first->second);
    jobs_.erase(first);
    queued_.store(jobs_.size(), std::memory_order_release);
  }
  const std::uint64_t start = clock_();
  job.run();
  const std::uint64_t cost = clock_() - start;
  if (cores_) cores_->job_done();
  const std::lock_guard lock(mutex_);  // before `job` (which may own the share) is destroyed
  job.share->last_cost = cost;
  job.share->next_tag = std::max(job.share->next_tag, tag + cost);
  return true;
}

bool FairWorkQueue::spin_for_job() {
  if (spinning_.exchange(true, std::memory_order_acquire)) return false;
  const auto until = std::chrono::steady_clock::now() + spin_;
  bool found = false;
  while (!(found = queued_.load(std::memory_order_acquire) > 0) &&
         std::chrono::steady_clock::now() < until) {
    std::this_thread::yield();
  }
  spinning_.store(false, std::memory_order_release);
  return found;
}

}  // namespace sweepd::server
