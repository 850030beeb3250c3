// run_subcommand: what every sweepctl subcommand does the same way — `--help` prints the usage,
// an unusable command line prints the problem and the usage (exit 2), input the work refuses
// prints its reason (exit 1), success exits 0.
//   parse  reads the arguments into the command's own options; returns "" or the problem
//   run    does the work; may throw std::exception with a message naming the file and reason
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace sweepd::cli {

int run_subcommand(std::string_view name, std::string_view usage,
                   const std::vector<std::string>& args,
                   const std::function<std::string(const std::vector<std::string>&)>& parse,
                   const std::function<int()>& run);

}  // namespace sweepd::cli
