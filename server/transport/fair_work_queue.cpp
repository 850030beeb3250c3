#include "server/transport/fair_work_queue.h"

#include <algorithm>
#include <asio/post.hpp>

namespace sweepd::server {

void FairWorkQueue::post(FairShare& share, std::function<void()> job) {
  {
    const std::lock_guard lock(mutex_);
    // Tags start at 1 so that a connection's first job (last_tag 0) lands on the virtual time.
    const std::uint64_t tag = std::max(virtual_time_, share.last_tag + 1);
    share.last_tag = tag;
    jobs_.emplace(std::pair{tag, arrivals_++}, std::move(job));
  }
  asio::post(pool_, [this] { run_one(); });
}

void FairWorkQueue::run_one() {
  std::function<void()> job;
  {
    const std::lock_guard lock(mutex_);
    auto first = jobs_.begin();  // never empty: one token per job
    virtual_time_ = first->first.first;
    job = std::move(first->second);
    jobs_.erase(first);
  }
  job();
}

}  // namespace sweepd::server
