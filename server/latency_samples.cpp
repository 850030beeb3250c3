#include "server/latency_samples.h"

#include <algorithm>

namespace sweepd::server {

void LatencySamples::add(std::uint64_t nanoseconds) {
  if (samples_.size() < kLatencySamples) {
    samples_.push_back(nanoseconds);
    return;
  }
  samples_[next_] = nanoseconds;
  next_ = (next_ + 1) % kLatencySamples;
}

protocol::LatencyPercentiles LatencySamples::percentiles() const {
  if (samples_.empty()) return {};
  std::vector<std::uint64_t> sorted = samples_;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double q) {
    return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
  };
  return protocol::LatencyPercentiles(at(0.5), at(0.9), at(0.99), sorted.back());
}

}  // namespace sweepd::server
