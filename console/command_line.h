// parse_command_line: runs a CLI11 parser (CLI/CLI.hpp, header-only) over main's arguments the
// same way in every sweepd program (sweepctl, render_frames, stream_poses, server_bench):
//   --help / -h          prints the usage on stdout (a subcommand's own    -> exit code 0
//                        usage after the subcommand: `sweepctl pose --help`)
//   a bad command line   unknown flag, a missing value or required flag,  -> exit code 2
//                        "12x" where a number is expected, a value out of range: prints
//                        "PROGRAM: reason" or "PROGRAM COMMAND: reason" (naming the flag)
//                        and a hint on stderr
//   with subcommands     none given, or an unknown one: the usage, or      -> exit code 2
//                        "PROGRAM: unknown command 'X'" and the usage, on stderr
// Returns nothing to go on, or the exit code for main to return. Rules between flags that
// CLI11 cannot state go in the app's or a subcommand's callback (run at the end of the parse),
// which throws CLI::ValidationError: they are reported like any other bad command line.
//
// whole_number(min, max): a validator for integer options: "12x" or "1.5" is refused as
// "expected a whole number from MIN to MAX, got '12x'", a number outside [min, max] as
// "N is outside MIN..MAX".
// add_choice: an option whose value is one of a few names, stored as the enum it names; any
// other name is a usage error listing the names.
// add_choice_list: an option whose value is a comma-separated list of such names; `take` gets
// each name's value in the order given; any other name is a usage error naming it.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
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

// The names of a comma-separated list ("a,b" -> {"a", "b"}; "" -> {}).
std::vector<std::string> split_list(const std::string& list);

template <typename Value>
CLI::Option* add_choice_list(CLI::App& app, const std::string& flag,
                             const std::map<std::string, Value>& choices,
                             const std::type_identity_t<std::function<void(const Value&)>>& take,
                             const std::string& help) {
  std::string names;
  for (const auto& [name, value] : choices) names += (names.empty() ? "" : ", ") + name;
  const CLI::Validator known(
      [choices, names](std::string& list) -> std::string {
        const std::vector<std::string> given = split_list(list);
        if (given.empty()) return "expected a comma-separated list of " + names + "; got none";
        for (const std::string& name : given)
          if (!choices.contains(name))
            return "expected a comma-separated list of " + names + "; got '" + name + "'";
        return "";
      },
      "");
  return app
      .add_option_function<std::string>(
          flag,
          [choices, take](const std::string& list) {
            for (const std::string& name : split_list(list)) take(choices.at(name));
          },
          help)
      ->check(known);
}

}  // namespace sweepd::console
