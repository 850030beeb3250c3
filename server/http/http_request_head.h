// read_request_head(bytes, max_bytes): the HTTP side port's reading of a request's head — the
// request line and headers up to the blank line — from the bytes received so far. The side port
// answers GET and HEAD of a few paths and keeps no connection open after its answer, so only the
// request line matters: the method, the path (the target without its query) and the version;
// the headers are skipped, never stored. Status: kIncomplete (no blank line yet, within
// max_bytes), kComplete, kTooLarge (max_bytes received and no end of the head), kBad (a request
// line that is not "METHOD /path HTTP/1.x", with `problem` saying why).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace sweepd::server {

// The most the side port reads of a head before it answers 431: a browser's or a kubelet's
// request head is well under 1 KiB.
inline constexpr std::size_t kMaxRequestHeadBytes = 8192;

struct HttpRequestHead {
  enum class Status { kIncomplete, kComplete, kTooLarge, kBad };
  Status status = Status::kIncomplete;
  std::string method;
  std::string path;     // from '/', without '?' and what follows
  std::string problem;  // kBad: why
};

HttpRequestHead read_request_head(std::string_view bytes, std::size_t max_bytes);

}  // namespace sweepd::server
