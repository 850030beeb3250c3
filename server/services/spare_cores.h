// SpareCores: how many of the deformation workers' cores no job holds, so that one large pose
// may split itself over them while the daemon is otherwise idle (one client's latency then falls
// with cores), while under many clients, whose jobs keep every worker busy, each pose runs on
// one thread and throughput is what it was.
//
//   SpareCores cores(workers);
//   cores.job_queued();  …  cores.job_done();     // FairWorkQueue, around every job
//   SpareCores::Loan extra = cores.borrow(3);      // up to 3 more threads for one pose
//   run_in_vertex_blocks(n, 1 + extra.count(), …); // the loan returns when `extra` ends
//
// A queued job counts as holding a core (a worker takes it in a moment), so a pose never borrows
// a core that another connection's job is about to need. A job that starts while a pose holds a
// loan still runs (the count goes below zero): the cores are shared for the rest of that pose,
// never refused.
#pragma once

#include <atomic>

namespace sweepd::server {

class SpareCores {
 public:
  explicit SpareCores(int cores) : spare_(cores) {}

  void job_queued() { spare_.fetch_sub(1, std::memory_order_relaxed); }
  void job_done() { spare_.fetch_add(1, std::memory_order_relaxed); }

  class Loan {
   public:
    Loan() = default;
    Loan(Loan&& other) noexcept : owner_(other.owner_), count_(other.count_) { other.count_ = 0; }
    Loan& operator=(Loan&&) = delete;
    ~Loan() {
      if (count_ > 0) owner_->spare_.fetch_add(count_, std::memory_order_relaxed);
    }
    int count() const { return count_; }

   private:
    friend class SpareCores;
    Loan(SpareCores* owner, int count) : owner_(owner), count_(count) {}
    SpareCores* owner_ = nullptr;
    int count_ = 0;
  };

  // Up to `wanted` cores that no job holds or waits for (none when every core is busy).
  Loan borrow(int wanted) {
    int spare = spare_.load(std::memory_order_relaxed);
    while (true) {
      const int granted = spare < wanted ? spare : wanted;
      if (granted <= 0) return {};
      if (spare_.compare_exchange_weak(spare, spare - granted, std::memory_order_relaxed))
        return {this, granted};
    }
  }

  int spare() const { return spare_.load(std::memory_order_relaxed); }

 private:
  std::atomic<int> spare_;  // cores minus queued and running jobs minus loans
};

}  // namespace sweepd::server
