#include "cli/self_check_report.h"

#include <cstdio>
#include <string>

namespace sweepd::cli {

void print_self_check(const deform::BoundModel& bound, const selfcheck::BindingVerdict& verdict,
                      std::optional<int> pairs_as_bound) {
  const int worse = verdict.worse_regions();
  std::string pairs = std::to_string(verdict.worse_pairs()) + " (pose, region) pairs";
  if (pairs_as_bound)
    pairs = std::to_string(*pairs_as_bound) + " (pose, region) pairs as bound, " +
            std::to_string(verdict.worse_pairs()) + " after adapting";
  const std::string regions = worse == 0 ? "nowhere worse than skinning"
                                         : "worse than skinning in " + std::to_string(worse) +
                                               " region" + (worse == 1 ? "" : "s");
  std::printf("self-check (%zu range-of-motion peaks, sweep against the better of LBS and DQS, "
              "edge stretch as l / l_rest, tolerance 1.02x): worse in %s; %s\n",
              verdict.pose_names.size(), pairs.c_str(), regions.c_str());
  for (const std::string& note : selfcheck::adaptation_notes(bound))
    std::printf("  adapted: %s\n", note.c_str());
  for (const std::string& warning : selfcheck::self_check_warnings(verdict))
    std::printf("  warning: %s\n", warning.c_str());
}

}  // namespace sweepd::cli
