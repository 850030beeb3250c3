// KeyEllipse: one key cross-section of a control sweep surface (paper §3.2).
//
// The ellipse is { centre + (o_x + a cos(θ)) X + (o_y + b sin(θ)) Y }, where the columns of
// R = mat3_cast(orientation) are X (major axis), Y (minor axis) and N (the plane normal, the
// direction the sweep advances). a >= b is the usual case but not required; both must be > 0.
// centre is the point the sweep's centre curve C(t) passes through (a joint key's joint);
// offset o = (o_x, o_y) places the ellipse in its plane off that point (a joint key's section
// centroid lies beside its joint), so the ellipse's own centre is centre + R (o_x, o_y, 0).
// o is zero for link keys; it turns with the key (it is in the key's own frame).
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace sweepd::deform {

struct KeyEllipse {
  glm::vec3 centre{0.0f};
  glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};  // (w, x, y, z), unit length
  float a = 1.0f;                                 // half-axis along R's first column
  float b = 1.0f;                                 // half-axis along R's second column
  glm::vec2 offset{0.0f};                         // (o_x, o_y) along R's first two columns
};

}  // namespace sweepd::deform
