// FairWorkQueue: the deformation workers' queue, fair between connections (start-time fair
// queuing, Goyal et al. 1996, with every job costing one unit). A FIFO queue made a connection
// opened while 32 others stream wait behind one queued pose of each (tens of milliseconds);
// here each connection's next job is tagged max(virtual time, that connection's last tag + 1),
// and a worker always runs the smallest tag (ties: arrival order). A new or idle connection
// starts at the virtual time, so its first pose runs next; busy connections take turns.
//
//   FairShare share;                              // one per connection, owned by it
//   queue.post(share, [] { ... });                // from any thread; runs on the pool
//
// post() puts one job in the queue and one token on the pool: each token runs whichever job
// is smallest then, so every job runs once, in fair order. The pool must be joined before the
// queue is destroyed (tokens hold the queue).
#pragma once

#include <asio/thread_pool.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <utility>

namespace sweepd::server {

struct FairShare {
  std::uint64_t last_tag = 0;  // the tag of the connection's latest job (guarded by the queue)
};

class FairWorkQueue {
 public:
  explicit FairWorkQueue(asio::thread_pool& pool) : pool_(pool) {}

  void post(FairShare& share, std::function<void()> job);

 private:
  void run_one();

  asio::thread_pool& pool_;
  std::mutex mutex_;
  std::map<std::pair<std::uint64_t, std::uint64_t>, std::function<void()>> jobs_;  // (tag, arrival)
  std::uint64_t virtual_time_ = 0;  // the tag of the job started last
  std::uint64_t arrivals_ = 0;
};

}  // namespace sweepd::server
