// log_event: sweepd's structured logs — one JSON object per line on stderr, e.g.
//   {"time":"2026-11-22T02:30:00.123Z","event":"connection_open","connection":3,"peer":"..."}
// Thread-safe: each line is written whole.
#pragma once

#include <nlohmann/json.hpp>
#include <string_view>

namespace sweepd::server {

// `fields`: a JSON object of extra keys (may be null).
void log_event(std::string_view event, nlohmann::json fields = nullptr);

}  // namespace sweepd::server
