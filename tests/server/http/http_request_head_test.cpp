// The side port's reading of a request head (server/http/http_request_head.h) and the answers
// it gives from memory (server/http/side_port_answers.h): a head is whole only at its blank
// line, too large past the bound, bad when its request line is not METHOD /path HTTP/1.x;
// /healthz and /readyz are answered at once, /metrics is left to its thread.
#include "server/http/http_request_head.h"

#include <gtest/gtest.h>

#include "server/http/side_port_answers.h"

namespace sweepd::server {
namespace {

using Status = HttpRequestHead::Status;

TEST(HttpRequestHead, WholeOnlyAtTheBlankLineWithThePathWithoutItsQuery) {
  const std::string request = "GET /readyz?verbose=1 HTTP/1.1\r\nHost: x\r\n\r\n";
  for (std::size_t n = 0; n < request.size(); ++n) {
    EXPECT_EQ(read_request_head(std::string_view(request).substr(0, n), 8192).status,
              Status::kIncomplete)
        << n;
  }
  const HttpRequestHead head = read_request_head(request, 8192);
  EXPECT_EQ(head.status, Status::kComplete);
  EXPECT_EQ(head.method, "GET");
  EXPECT_EQ(head.path, "/readyz");
  EXPECT_EQ(read_request_head("HEAD /healthz HTTP/1.0\n\n", 8192).status, Status::kComplete);
}

TEST(HttpRequestHead, TooLargeAndBadHeadsAreNamed) {
  const std::string endless = "GET / HTTP/1.1\r\nX: " + std::string(100, 'a');
  EXPECT_EQ(read_request_head(endless, 64).status, Status::kTooLarge);
  EXPECT_EQ(read_request_head(endless + "\r\n\r\n", 64).status, Status::kTooLarge);
  for (const char* line :
       {"GET\r\n\r\n", "GET /x\r\n\r\n", "GET x HTTP/1.1\r\n\r\n", "GET /x HTTP/2\r\n\r\n",
        "G(T /x HTTP/1.1\r\n\r\n", " /x HTTP/1.1\r\n\r\n", "GET /a b HTTP/1.1\r\n\r\n"}) {
    const HttpRequestHead head = read_request_head(line, 8192);
    EXPECT_EQ(head.status, Status::kBad) << line;
    EXPECT_FALSE(head.problem.empty()) << line;
  }
}

TEST(SidePortAnswers, ProbesAtOnceMetricsOnItsThreadOtherMethodsRefused) {
  Readiness readiness;
  const auto ask = [&](const std::string& method, const std::string& path) {
    return answer_at_once(read_request_head(method + " " + path + " HTTP/1.1\r\n\r\n", 8192),
                          readiness, nullptr);
  };
  EXPECT_EQ(ask("GET", "/readyz")->status, 503);
  readiness.set(Readiness::Stage::kAccepting);
  EXPECT_EQ(ask("GET", "/readyz")->status, 200);
  EXPECT_EQ(ask("GET", "/readyz")->body, "accepting\n");
  EXPECT_EQ(ask("GET", "/healthz")->body, "ok\n");
  EXPECT_FALSE(ask("GET", "/metrics").has_value());
  EXPECT_EQ(ask("GET", "/nothing")->status, 404);
  EXPECT_EQ(ask("GET", "/viewer/a/b")->status, 404);
  EXPECT_EQ(ask("POST", "/healthz")->status, 405);
  const std::string head_only = http_response_bytes(*ask("HEAD", "/healthz"), true);
  EXPECT_EQ(head_only,
            "HTTP/1.1 200 OK\r\nContent-Type: text/plain; charset=utf-8\r\nContent-Length: 3\r\n"
            "Connection: close\r\n\r\n");
}

}  // namespace
}  // namespace sweepd::server
