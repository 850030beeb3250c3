#include "console/command_line.h"

#include <algorithm>
#include <charconv>
#include <cstdio>

namespace sweepd::console {

namespace {

// "sweepctl", or "sweepctl pose" once the pose subcommand was chosen.
std::string command_name(const CLI::App& app) {
  std::string name = app.get_name();
  for (const CLI::App* chosen = &app; !chosen->get_subcommands().empty();) {
    chosen = chosen->get_subcommands().front();
    name += " " + chosen->get_name();
  }
  return name;
}

bool has_subcommands(const CLI::App& app) {
  return !app.get_subcommands([](const CLI::App*) { return true; }).empty();
}

}  // namespace

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  const std::string program = app.get_name();
  try {
    app.parse(argc, argv);
    if (has_subcommands(app) && app.get_subcommands().empty()) {
      std::fputs(app.help().c_str(), stderr);
      return 2;
    }
    return std::nullopt;
  } catch (const CLI::Success&) {  // --help
    std::fputs(app.help().c_str(), stdout);
    return 0;
  } catch (const CLI::ParseError& error) {
    const std::vector<std::string> extras = app.remaining();
    if (dynamic_cast<const CLI::ExtrasError*>(&error) && has_subcommands(app) &&
        app.get_subcommands().empty() && !extras.empty() && !extras.front().starts_with("-")) {
      std::fprintf(stderr, "%s: unknown command '%s'\n\n%s", program.c_str(),
                   extras.front().c_str(), app.help().c_str());
      return 2;
    }
    const std::string name = command_name(app);
    std::fprintf(stderr, "%s: %s\n(%s --help lists the flags)\n", name.c_str(), error.what(),
                 name.c_str());
    return 2;
  }
}

CLI::Validator whole_number(long long min, long long max) {
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        long long value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || error != std::errc() || end != text.data() + text.size())
          return "expected a whole number from " + std::to_string(min) + " to " +
                 std::to_string(max) + ", got '" + text + "'";
        if (value < min || value > max)
          return text + " is outside " + std::to_string(min) + ".." + std::to_string(max);
        return "";
      },
      "INT in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
}

std::vector<std::string> split_list(const std::string& list) {
  std::vector<std::string> names;
  for (std::size_t start = 0; start < list.size();) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    names.push_back(list.substr(start, comma - start));
    start = comma + 1;
  }
  return names;
}

}  // namespace sweepd::console
