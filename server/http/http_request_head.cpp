#include "server/http/http_request_head.h"

#include <algorithm>

namespace sweepd::server {
namespace {

using Status = HttpRequestHead::Status;

HttpRequestHead bad(std::string problem) {
  HttpRequestHead head;
  head.status = Status::kBad;
  head.problem = std::move(problem);
  return head;
}

// RFC 9110 token characters, the only ones a method may have.
bool token_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
         std::string_view("!#$%&'*+-.^_`|~").find(c) != std::string_view::npos;
}

}  // namespace

HttpRequestHead read_request_head(std::string_view bytes, std::size_t max_bytes) {
  // The head ends at an empty line; bare LF line ends are tolerated (RFC 9112 section 2.2).
  std::size_t end = bytes.find("\r\n\r\n");
  if (end == std::string_view::npos) end = bytes.find("\n\n");
  if (end == std::string_view::npos || end > max_bytes) {
    if (bytes.size() >= max_bytes) {
      HttpRequestHead head;
      head.status = Status::kTooLarge;
      return head;
    }
    return {};
  }
  std::string_view line = bytes.substr(0, bytes.find('\n'));
  if (line.ends_with('\r')) line.remove_suffix(1);
  const std::size_t first_space = line.find(' ');
  const std::size_t last_space = line.rfind(' ');
  if (first_space == std::string_view::npos || first_space == last_space) {
    return bad("the request line is not METHOD TARGET VERSION");
  }
  const std::string_view method = line.substr(0, first_space);
  const std::string_view target = line.substr(first_space + 1, last_space - first_space - 1);
  const std::string_view version = line.substr(last_space + 1);
  if (method.empty() || !std::all_of(method.begin(), method.end(), token_char)) {
    return bad("the method is not a token");
  }
  if (version != "HTTP/1.1" && version != "HTTP/1.0") return bad("not HTTP/1.0 or HTTP/1.1");
  if (!target.starts_with('/') || target.find(' ') != std::string_view::npos) {
    return bad("the target is not a path from /");
  }
  HttpRequestHead head;
  head.status = Status::kComplete;
  head.method = method;
  head.path = target.substr(0, target.find('?'));
  return head;
}

}  // namespace sweepd::server
