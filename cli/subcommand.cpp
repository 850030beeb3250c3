#include "cli/subcommand.h"

#include <cstdio>
#include <exception>

namespace sweepd::cli {

int run_subcommand(std::string_view name, std::string_view usage,
                   const std::vector<std::string>& args,
                   const std::function<std::string(const std::vector<std::string>&)>& parse,
                   const std::function<int()>& run) {
  const std::string prefix = "sweepctl " + std::string(name);
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::fwrite(usage.data(), 1, usage.size(), stdout);
    return 0;
  }
  if (const std::string problem = parse(args); !problem.empty()) {
    std::fprintf(stderr, "%s: %s\n\n%.*s", prefix.c_str(), problem.c_str(),
                 static_cast<int>(usage.size()), usage.data());
    return 2;
  }
  try {
    return run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", prefix.c_str(), e.what());
    return 1;
  }
}

}  // namespace sweepd::cli
