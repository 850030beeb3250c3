// FairWorkQueue: the deformation workers' queue, fair between connections (start-time fair
// queuing, Goyal et al. 1996, charged by the worker time each job took, as Linux's CFS charges
// a task's run time). A FIFO queue made a connection opened while 32 others stream wait behind
// one queued pose of each (tens of milliseconds); here each connection's next job is tagged
// max(virtual time, that connection's next tag), and a worker always runs the smallest tag
// (ties: arrival order). A new or idle connection starts at the virtual time, so its first pose
// runs next; busy connections take turns in proportion to the worker time they use. A job
// that took microseconds (a model already loaded, looked up) costs microseconds: with one
// unit per job, a new connection's LoadModel cost it a whole turn of 32 others before its first
// pose.
//
//   FairShare share;                              // one per connection, owned by it
//   queue.post(share, [] { ... });                // from any thread; runs on the pool
//
// post() puts one job in the queue and one token on the pool: each token runs whichever job
// is smallest then, so every job runs once, in fair order. A job is charged when it ends; jobs
// of one connection queued before then are spaced by its last job's cost. The pool must be
// joined before the queue is destroyed (tokens hold the queue), and a share must outlive its
// jobs.
//
// With a `spin`, a worker that has finished a job polls the queue for up to that long before it
// goes back to sleep in the pool (one worker at a time, yielding its core to any thread that
// wants it). A sleeping worker is woken by the pool's condition variable, and on a virtual
// machine a thread woken on an idle core runs only after the hypervisor wakes that core: a
// client sending one pose at a time paid that wake-up on every pose (docs/performance.md, "server_bench").
// A job a spinning worker takes leaves its token nothing to run: the token returns at once.
#pragma once

#include <asio/thread_pool.hpp>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <utility>

#include "server/services/spare_cores.h"

namespace sweepd::server {

struct FairShare {              // guarded by the queue
  std::uint64_t next_tag = 0;   // where the connection's next job starts, in worker nanoseconds
  std::uint64_t last_cost = 0;  // what its latest finished job took
};

class FairWorkQueue {
 public:
  using Clock = std::function<std::uint64_t()>;  // nanoseconds, monotonic

  // `clock` measures what each job costs: the steady clock, or a test's own. `spin`: how long
  // a worker that finished a job polls for the next one before it sleeps (zero: not at all).
  // `cores`, when given, is told of every job from post() until it has run (SpareCores).
  explicit FairWorkQueue(asio::thread_pool& pool, Clock clock = steady_nanoseconds,
                         std::chrono::microseconds spin = {}, SpareCores* cores = nullptr);

  void post(FairShare& share, std::function<void()> job);

  static std::uint64_t steady_nanoseconds();

 private:
  struct Job {
    FairShare* share;
    std::function<void()> run;
  };
  void run_one();       // a token: runs the smallest job, then those it finds while spinning
  bool run_next();      // runs the smallest job, if any
  bool spin_for_job();  // true when a job was queued within spin_ (false: another worker spins)

  asio::thread_pool& pool_;
  Clock clock_;
  SpareCores* cores_;
  std::chrono::microseconds spin_;
  std::atomic<std::size_t> queued_{0};  // jobs_.size(), read without the lock while spinning
  std::atomic<bool> spinning_{false};   // a worker is polling
  std::mutex mutex_;
  std::map<std::pair<std::uint64_t, std::uint64_t>, Job> jobs_;  // (tag, arrival)
  std::uint64_t virtual_time_ = 0;                               // the largest tag started yet
  std::uint64_t arrivals_ = 0;
};

}  // namespace sweepd::server
