// The /metrics page without a daemon: latencies land in the bucket whose bound holds them
// (Prometheus buckets are "≤ le") and the buckets are cumulative; model names are escaped in
// label values; before the server serves, only the process and readiness lines are there.
#include "server/http/metrics_text.h"

#include <gtest/gtest.h>

#include "tests/server/http_probe.h"

namespace sweepd::test {
namespace {

using server::Readiness;

TEST(MetricsText, LatenciesFillCumulativeBucketsInSeconds) {
  server::ServerSnapshot snapshot;
  snapshot.traffic.pose_latency.add(1'000'000);       // 1 ms: exactly a bound, counted in it
  snapshot.traffic.pose_latency.add(1'000'001);       // just above: the next bucket (2.5 ms)
  snapshot.traffic.pose_latency.add(30'000'000'000);  // 30 s: above every bound
  const std::string page = server::format_metrics(
      &snapshot, {.resident_bytes = 4096, .start_time_seconds = 1.5}, Readiness::Stage::kAccepting);
  const std::string bucket = "sweepd_pose_latency_seconds_bucket";
  EXPECT_EQ(metric(page, bucket + "{le=\"0.0005\"}"), 0.0);
  EXPECT_EQ(metric(page, bucket + "{le=\"0.001\"}"), 1.0);
  EXPECT_EQ(metric(page, bucket + "{le=\"0.0025\"}"), 2.0);
  EXPECT_EQ(metric(page, bucket + "{le=\"10\"}"), 2.0);
  EXPECT_EQ(metric(page, bucket + "{le=\"+Inf\"}"), 3.0);
  EXPECT_EQ(metric(page, "sweepd_pose_latency_seconds_count"), 3.0);
  // The sum in seconds; 1e-9 s: one nanosecond, the resolution of what was added.
  EXPECT_NEAR(metric(page, "sweepd_pose_latency_seconds_sum"), 30.002000001, 1e-9);
  EXPECT_EQ(metric(page, "sweepd_ready"), 1.0);
  EXPECT_EQ(metric(page, "sweepd_process_resident_memory_bytes"), 4096.0);
  EXPECT_NE(page.find("# TYPE sweepd_pose_latency_seconds histogram\n"), std::string::npos);
}

TEST(MetricsText, ModelNamesAreEscapedInLabels) {
  server::ServerSnapshot snapshot;
  snapshot.models.push_back({.id = 3, .name = "a\"b\\c\nd", .poses = 5, .errors = 0});
  const std::string page = server::format_metrics(&snapshot, {}, Readiness::Stage::kAccepting);
  EXPECT_EQ(metric(page, R"(sweepd_model_poses_total{model="a\"b\\c\nd",id="3"})"), 5.0) << page;
}

TEST(MetricsText, BeforeServingOnlyProcessAndReadiness) {
  const std::string page = server::format_metrics(nullptr, {}, Readiness::Stage::kRestoringStore);
  EXPECT_EQ(metric(page, "sweepd_ready"), 0.0);
  EXPECT_EQ(page.find("sweepd_requests_total"), std::string::npos);
  EXPECT_NE(page.find("sweepd_process_start_time_seconds"), std::string::npos);
}

}  // namespace
}  // namespace sweepd::test
