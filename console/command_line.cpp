#include "console/command_line.h"

#include <charconv>
#include <cstdio>

namespace sweepd::console {

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::Success&) {  // --help
    std::fputs(app.help().c_str(), stdout);
    return 0;
  } catch (const CLI::ParseError& error) {
    std::fprintf(stderr, "%s: %s\n(%s --help lists the flags)\n", app.get_name().c_str(),
                 error.what(), app.get_name().c_str());
    return 2;
  }
}

CLI::Validator whole_number(long long min, long long max) {
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        long long value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || error != std::errc() || end != text.data() + text.size() ||
            value < min || value > max)
          return "expected a whole number from " + std::to_string(min) + " to " +
                 std::to_string(max) + ", got '" + text + "'";
        return "";
      },
      "INT in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
}

}  // namespace sweepd::console
