#include "deform/edits/rest_key_edit.h"

#include <cmath>
#include <glm/gtc/quaternion.hpp>

#include "deform/binding/rest_sweep.h"
#include "deform/rig/rig_map.h"
#include "deform/sweep/swept_volume.h"

namespace sweepd::deform {

namespace {

// "left_arm" → the sweep whose part prints as "left arm", or -1.
int find_sweep(const BoundModel& bound, std::string_view name) {
  std::string spaced(name);
  for (char& c : spaced)
    if (c == '_') c = ' ';
  for (std::size_t s = 0; s < bound.sweeps.size(); ++s)
    if (spaced == to_string(bound.sweeps[s].part)) return static_cast<int>(s);
  return -1;
}

}  // namespace

std::string apply_rest_key_edit(BoundModel& bound, const RestKeyEdit& edit) {
  const int s = find_sweep(bound, edit.sweep);
  if (s < 0) return "no sweep named '" + edit.sweep + "' in this model";
  std::vector<KeyEllipse>& keys = bound.sweeps[s].rest_keys;
  if (edit.key < 0 || edit.key >= static_cast<int>(keys.size()))
    return "sweep '" + edit.sweep + "' has keys 0.." + std::to_string(keys.size() - 1) + ", not " +
           std::to_string(edit.key);
  const bool finite = std::isfinite(edit.centre_offset.x) && std::isfinite(edit.centre_offset.y) &&
                      std::isfinite(edit.centre_offset.z) && std::isfinite(edit.a) &&
                      std::isfinite(edit.b) && std::isfinite(edit.twist_radians);
  if (!finite) return "the edit holds a NaN or infinite value";
  if (edit.a < 0.0f || edit.b < 0.0f) return "half-axes must be positive (0 keeps them)";
  KeyEllipse& key = keys[edit.key];
  key.centre += edit.centre_offset;
  if (edit.a > 0.0f) key.a = edit.a;
  if (edit.b > 0.0f) key.b = edit.b;
  key.orientation = glm::normalize(key.orientation *
                                   glm::angleAxis(edit.twist_radians, glm::vec3(0.0f, 0.0f, 1.0f)));
  // The vertices keep their coordinates: the skin follows the edited key (in every pose, the
  // rest pose included); the volume that preservation holds is the edited sweep's.
  bound.sweeps[s].rest_volume = sweep_volume(rest_sweep(bound.sweeps[s], bound.options));
  return "";
}

}  // namespace sweepd::deform
