// name_list: a few names (joints, models) for a one-line message, so a warning or an error
// names what it is about without growing with the rig: the first `shown` names joined by ", ",
// then "and N more" for the rest ("LThumb, LeftFingerBase and 3 more"). Empty for no names.
#pragma once

#include <cstddef>
#include <span>
#include <string>

namespace sweepd::motion {

// Twelve names keep a warning on one or two terminal lines and still show a hand's fingers.
inline constexpr std::size_t kListedNames = 12;

std::string name_list(std::span<const std::string> names, std::size_t shown = kListedNames);

}  // namespace sweepd::motion
