// format_metrics: the /metrics page in the Prometheus text exposition format (version 0.0.4):
// every metric named sweepd_*, with HELP and TYPE lines, counters ending in _total, latencies
// as histograms in seconds (buckets kLatencyBucketSeconds). Inputs: `server`, the Server's
// counters (null before it serves or once it has stopped: then only the process and
// readiness lines), `process` (resident memory, start time) and the readiness stage.
// Returns the page (a few KiB).
#pragma once

#include <string>

#include "server/http/process_stats.h"
#include "server/readiness.h"
#include "server/transport/server_snapshot.h"

namespace sweepd::server {

inline constexpr char kMetricsContentType[] = "text/plain; version=0.0.4; charset=utf-8";

std::string format_metrics(const ServerSnapshot* server, const ProcessStats& process,
                           Readiness::Stage stage);

}  // namespace sweepd::server
