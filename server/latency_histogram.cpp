#include "server/latency_histogram.h"

#include <algorithm>

namespace sweepd::server {

void LatencyHistogram::add(std::uint64_t nanoseconds) {
  const double seconds = static_cast<double>(nanoseconds) * 1e-9;
  // Prometheus buckets are "less than or equal to" their bound.
  const auto bound =
      std::lower_bound(kLatencyBucketSeconds.begin(), kLatencyBucketSeconds.end(), seconds);
  ++counts_[static_cast<std::size_t>(bound - kLatencyBucketSeconds.begin())];
  ++count_;
  sum_ns_ += nanoseconds;
}

}  // namespace sweepd::server
