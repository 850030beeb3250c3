// LatencyHistogram: counts of latencies in fixed buckets (upper bounds in seconds,
// kLatencyBucketSeconds) with their sum, for the Prometheus histograms of /metrics — unlike
// LatencySamples it forgets nothing, so rates and quantiles over any window can be computed
// by the scraper. Not thread-safe: kept on the I/O thread, copied for a snapshot.
// add(nanoseconds): one observation. bucket_counts(): per bucket (not cumulative), size
// kLatencyBuckets + 1 (the last: above every bound).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace sweepd::server {

// From half a millisecond (a small model's pose) to 10 s (a large position map on llvmpipe).
inline constexpr std::array<double, 14> kLatencyBucketSeconds = {
    0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0};
inline constexpr std::size_t kLatencyBuckets = kLatencyBucketSeconds.size();

class LatencyHistogram {
 public:
  void add(std::uint64_t nanoseconds);

  const std::array<std::uint64_t, kLatencyBuckets + 1>& bucket_counts() const { return counts_; }
  std::uint64_t count() const { return count_; }
  double sum_seconds() const { return static_cast<double>(sum_ns_) * 1e-9; }

 private:
  std::array<std::uint64_t, kLatencyBuckets + 1> counts_{};
  std::uint64_t count_ = 0;
  std::uint64_t sum_ns_ = 0;
};

}  // namespace sweepd::server
