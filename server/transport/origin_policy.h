// origin_policy: which browser pages may open a WebSocket to sweepd (--ws-allowed-origin).
// A page's browser sends its Origin ("https://viewer.example:8443") with the upgrade request;
// a program that is not a browser sends none. The token in Hello still authenticates every
// client: the Origin check keeps other web sites' pages (which a user's browser would run
// with the user's network access) from reaching the daemon at all.
//
// origin_refusal(origin, host, allowed): "" when the upgrade may go on, else the reason.
//   origin  the Origin header, "" when absent: always allowed (not a browser)
//   host    the Host header ("127.0.0.1:7879")
//   allowed --ws-allowed-origin's entries, each an exact origin (scheme://host[:port],
//           compared without regard to case) or "*" (any); empty (the default): only an
//           Origin naming the host the request was sent to (the page was served by this host,
//           on any port and scheme), so a viewer on the same machine or behind the same name works
//           and another site's page does not. "null" (a file:// page) only with "*" or "null".
// Plain C++17 (websocket_session.cpp includes it).
#pragma once

#include <string>
#include <vector>

namespace sweepd::server {

std::string origin_refusal(const std::string& origin, const std::string& host,
                           const std::vector<std::string>& allowed);

}  // namespace sweepd::server
