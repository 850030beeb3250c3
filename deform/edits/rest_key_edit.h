// RestKeyEdit: replace one rest key ellipse of a bound model (sweepd's EditKeyEllipse) — move its
// centre, set its half-axes, turn it about the sweep's axis. The vertices keep their sweep
// coordinates, so the skin follows the edited control surface in every pose, the rest pose
// included (sculpting: a larger half-axis makes the limb thicker there); the sweep's rest volume,
// which volume preservation holds, becomes the edited one. (The pose-dependent corrections of
// paper §4.2 are KeyEllipseEdits; this changes the key itself.)
#pragma once

#include <glm/glm.hpp>
#include <string>
#include <string_view>

#include "deform/binding/bound_model.h"

namespace sweepd::deform {

struct RestKeyEdit {
  std::string sweep;              // "torso", "neck", "left_arm", "right_arm", "left_leg", ...
  int key = -1;                   // along the sweep, from its root end
  glm::vec3 centre_offset{0.0f};  // model space, added to the key's centre
  float a = 0.0f, b = 0.0f;       // new half-axes in metres; 0 keeps the current one
  float twist_radians = 0.0f;     // about the key's normal (the sweep's axis)
};

// Applies the edit to `bound`. Returns "" or why the edit is refused (an
// unknown sweep, a key out of range, a non-finite or negative value); refused edits change
// nothing.
std::string apply_rest_key_edit(BoundModel& bound, const RestKeyEdit& edit);

}  // namespace sweepd::deform
