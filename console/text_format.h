// Numbers as people read them, the same in every program's output and in the server's errors.
#pragma once

#include <cstdint>
#include <string>

namespace sweepd::console {

// 14517 -> "14,517".
std::string with_thousands(std::int64_t n);

}  // namespace sweepd::console
