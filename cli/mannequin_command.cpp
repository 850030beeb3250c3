#include <cstdio>

#include "cli/commands.h"

namespace sweepd::cli {
int run_mannequin(const std::vector<std::string>&) {
  std::fprintf(stderr, "sweepctl mannequin: not built yet\n");
  return 1;
}
}  // namespace sweepd::cli
