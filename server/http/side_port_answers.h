// The HTTP side port's answers (server/http/http_side_port.h), apart from the sockets:
// answer_at_once(head, readiness, viewer) — every answer that needs nothing but memory: /healthz,
// /readyz (from `readiness`, one atomic), /viewer files, 404, 405 for a method other than GET or
// HEAD, 414 for a viewer name past its bound; nullopt for /metrics, which waits for the
// protocol's I/O thread and so is answered on a thread of its own. http_response_bytes: the
// answer as sent (HTTP/1.1, Content-Length, Connection: close; the headers only for HEAD).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "server/http/http_request_head.h"
#include "server/http/viewer_files.h"
#include "server/readiness.h"

namespace sweepd::server {

inline constexpr char kPlainText[] = "text/plain; charset=utf-8";

struct HttpAnswer {
  int status = 200;
  std::string content_type = kPlainText;
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  // beyond the ones always sent
};

std::optional<HttpAnswer> answer_at_once(const HttpRequestHead& head, const Readiness& readiness,
                                         const ViewerFiles* viewer);

std::string http_response_bytes(const HttpAnswer& answer, bool head_only);

}  // namespace sweepd::server
