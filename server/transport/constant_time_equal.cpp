#include "server/transport/constant_time_equal.h"

#include <algorithm>
#include <cstddef>

namespace sweepd::server {

bool constant_time_equal(std::string_view secret, std::string_view candidate) {
  // Every byte of the longer string is visited; a length difference counts as a mismatch.
  const std::size_t length = std::max(secret.size(), candidate.size());
  volatile unsigned char difference = secret.size() == candidate.size() ? 0 : 1;
  for (std::size_t i = 0; i < length; ++i) {
    const unsigned char a = i < secret.size() ? static_cast<unsigned char>(secret[i]) : 0;
    const unsigned char b = i < candidate.size() ? static_cast<unsigned char>(candidate[i]) : 0;
    difference = difference | (a ^ b);
  }
  return difference == 0;
}

}  // namespace sweepd::server
