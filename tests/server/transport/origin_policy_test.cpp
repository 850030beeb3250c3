// Which browser Origins may open a WebSocket to sweepd (server/transport/origin_policy.h): by
// default none but a page of the host the request names; with --ws-allowed-origin, exactly
// those listed (or any with "*"). A client without Origin is no browser and always passes.
#include "server/transport/origin_policy.h"

#include <gtest/gtest.h>

namespace sweepd::server {
namespace {

TEST(OriginPolicy, ByDefaultOnlyPagesOfTheHostTheRequestNames) {
  EXPECT_EQ(origin_refusal("", "127.0.0.1:7879", {}), "");
  EXPECT_EQ(origin_refusal("http://127.0.0.1:8080", "127.0.0.1:7879", {}), "");
  EXPECT_EQ(origin_refusal("https://Sweepd.Example", "sweepd.example:7879", {}), "");
  EXPECT_EQ(origin_refusal("http://[::1]:8080", "[::1]:7879", {}), "");
  const std::string refusal = origin_refusal("https://evil.example", "127.0.0.1:7879", {});
  EXPECT_NE(refusal.find("https://evil.example"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("--ws-allowed-origin"), std::string::npos) << refusal;
  // A host that only starts like the right one, a file:// page, and no Host header.
  EXPECT_NE(origin_refusal("http://127.0.0.10", "127.0.0.1:7879", {}), "");
  EXPECT_NE(origin_refusal("null", "127.0.0.1:7879", {}), "");
  EXPECT_NE(origin_refusal("http://127.0.0.1", "", {}), "");
}

TEST(OriginPolicy, AnAllowListIsExactAndStarAllowsAny) {
  const std::vector<std::string> allowed = {"https://viewer.example", "http://lab.example:8080"};
  EXPECT_EQ(origin_refusal("https://viewer.example", "sweepd:7879", allowed), "");
  EXPECT_EQ(origin_refusal("HTTP://LAB.EXAMPLE:8080", "sweepd:7879", allowed), "");
  EXPECT_EQ(origin_refusal("", "sweepd:7879", allowed), "");
  EXPECT_NE(origin_refusal("http://viewer.example", "sweepd:7879", allowed), "");    // scheme
  EXPECT_NE(origin_refusal("http://lab.example:8081", "sweepd:7879", allowed), "");  // port
  // With a list, the same host is no longer allowed unless listed.
  EXPECT_NE(origin_refusal("http://sweepd:8080", "sweepd:7879", allowed), "");
  EXPECT_EQ(origin_refusal("null", "sweepd:7879", {"null"}), "");
  EXPECT_EQ(origin_refusal("https://anything.example", "sweepd:7879", {"*"}), "");
}

}  // namespace
}  // namespace sweepd::server
