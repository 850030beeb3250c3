// KeyEllipse: one key cross-section of a control sweep surface (paper §3.2).
//
// The ellipse is { centre + a cos(θ) X + b sin(θ) Y }, where the columns of
// R = mat3_cast(orientation) are X (major axis), Y (minor axis) and N (the plane normal, the
// direction the sweep advances). a >= b is the usual case but not required; both must be > 0.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace sweepd::deform {

struct KeyEllipse {
  glm::vec3 centre{0.0f};
  glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};  // (w, x, y, z), unit length
  float a = 1.0f;                                 // half-axis along R's first column
  float b = 1.0f;                                 // half-axis along R's second column
};

}  // namespace sweepd::deform
