// Small text helpers shared by sweepctl's commands (numbers with thousands separators).
#pragma once

#include <cstdint>
#include <string>

namespace sweepd::cli {

// 14517 -> "14,517".
std::string with_thousands(std::int64_t n);

}  // namespace sweepd::cli
