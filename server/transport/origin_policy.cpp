#include "server/transport/origin_policy.h"

#include <algorithm>
#include <cctype>
#include <string_view>

namespace sweepd::server {
namespace {

bool same_text_any_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

// "host", "host:port", "[v6]:port" -> the host without its port.
std::string_view host_part(std::string_view authority) {
  if (authority.starts_with('[')) return authority.substr(0, authority.find(']') + 1);
  return authority.substr(0, authority.find(':'));
}

}  // namespace

std::string origin_refusal(const std::string& origin, const std::string& host,
                           const std::vector<std::string>& allowed) {
  if (origin.empty()) return "";
  if (!allowed.empty()) {
    for (const std::string& entry : allowed)
      if (entry == "*" || same_text_any_case(entry, origin)) return "";
    return "Origin " + origin + " is not one of --ws-allowed-origin";
  }
  const std::size_t scheme_end = origin.find("://");
  if (scheme_end != std::string::npos && !host.empty()) {
    const std::string_view authority = std::string_view(origin).substr(scheme_end + 3);
    if (same_text_any_case(host_part(authority), host_part(host))) return "";
  }
  return "Origin " + origin + " is not the host the request was sent to (" + host +
         "); allow it with --ws-allowed-origin";
}

}  // namespace sweepd::server
