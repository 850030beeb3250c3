#include <cstdio>

#include "cli/commands.h"

namespace sweepd::cli {
int run_inspect(const std::vector<std::string>&) {
  std::fprintf(stderr, "sweepctl inspect: not built yet\n");
  return 1;
}
}  // namespace sweepd::cli
