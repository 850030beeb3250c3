// parse_command_line: runs a CLI11 parser (CLI/CLI.hpp, header-only) over main's arguments the
// same way in every sweepd program (render_frames, stream_poses, server_bench):
//   --help / -h          prints the usage on stdout                       -> exit code 0
//   a bad command line   unknown flag, a missing value or required flag,  -> exit code 2
//                        "12x" where a number is expected, a value out of range: prints
//                        "PROGRAM: reason" (naming the flag) and a hint on stderr
// Returns nothing to go on, or the exit code for main to return.
//
// whole_number(min, max): a validator for integer options: "12x", "1.5" or a number outside
// [min, max] is refused as "expected a whole number from MIN to MAX, got '12x'".
// add_choice: an option whose value is one of a few names, stored as the enum it names; any
// other name is a usage error listing the names.
#pragma once

#include <CLI/CLI.hpp>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace sweepd::console {

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv);

CLI::Validator whole_number(long long min, long long max);

template <typename Enum>
CLI::Option* add_choice(CLI::App& app, const std::string& flag, Enum& target,
                        const std::map<std::string, Enum>& choices, const std::string& help) {
  std::vector<std::string> names;
  for (const auto& [name, value] : choices) names.push_back(name);
  return app.add_option(flag, help)
      ->check(CLI::IsMember(names))
      ->each([&target, choices](const std::string& name) { target = choices.at(name); });
}

}  // namespace sweepd::console
