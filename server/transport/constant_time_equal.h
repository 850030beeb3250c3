// constant_time_equal: compares a secret (the auth token) with a candidate in time that
// depends only on their lengths, never on where they first differ.
#pragma once

#include <string_view>

namespace sweepd::server {

bool constant_time_equal(std::string_view secret, std::string_view candidate);

}  // namespace sweepd::server
