// HttpSidePort in this process, with a Readiness the test moves through every stage: /readyz
// answers 503 naming each stage before accepting, 200 while accepting, 503 while draining;
// /healthz 200 throughout; /metrics without a serving Server has the readiness line only.
// Asked with curl (skipped without it).
#include "server/http/http_side_port.h"

#include <gtest/gtest.h>

#include "tests/server/http_probe.h"

namespace sweepd::test {
namespace {

using server::Readiness;

TEST(HttpSidePort, ReadyzFollowsEveryStage) {
  if (!have_program("curl")) GTEST_SKIP() << "curl is not installed";
  Readiness readiness;
  server::HttpSidePort http("127.0.0.1", 0, readiness, [] { return std::nullopt; });
  ASSERT_GT(http.port(), 0);
  const std::pair<Readiness::Stage, int> expected[] = {
      {Readiness::Stage::kRestoringStore, 503},
      {Readiness::Stage::kBindingDefaultModel, 503},
      {Readiness::Stage::kOpeningListeners, 503},
      {Readiness::Stage::kAccepting, 200},
      {Readiness::Stage::kDraining, 503}};
  for (const auto& [stage, status] : expected) {
    readiness.set(stage);
    const HttpReply ready = curl_get(http.port(), "/readyz");
    EXPECT_EQ(ready.status, status) << Readiness::describe(stage);
    EXPECT_EQ(ready.body, std::string(Readiness::describe(stage)) + "\n");
    EXPECT_EQ(curl_get(http.port(), "/healthz").status, 200);
  }
  const HttpReply metrics = curl_get(http.port(), "/metrics");
  EXPECT_EQ(metrics.status, 200);
  EXPECT_NE(metrics.body.find("\nsweepd_ready 0\n"), std::string::npos) << metrics.body;
  EXPECT_EQ(metrics.body.find("sweepd_requests_total"), std::string::npos);
}

}  // namespace
}  // namespace sweepd::test
