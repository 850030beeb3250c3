#include "cli/text_format.h"

namespace sweepd::cli {

std::string with_thousands(std::int64_t n) {
  std::string digits = std::to_string(n < 0 ? -n : n);
  for (int i = static_cast<int>(digits.size()) - 3; i > 0; i -= 3) digits.insert(i, ",");
  return n < 0 ? "-" + digits : digits;
}

}  // namespace sweepd::cli

#include <charconv>

namespace sweepd::cli {

bool parse_int(const std::string& text, int min, int max, int& value) {
  int parsed = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), parsed);
  if (error != std::errc() || end != text.data() + text.size() || parsed < min || parsed > max)
    return false;
  value = parsed;
  return true;
}

}  // namespace sweepd::cli
