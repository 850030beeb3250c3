// Unity's frame and glTF's: Unity is left-handed and Y-up, glTF (and every model sweepd holds)
// right-handed and Y-up. VMC sends positions and rotations in Unity's frame; sweepd mirrors X
// to read them, as UniVRM does for VRM 1.0: a humanoid faces +Z in both (Unity's forward, the
// glTF spec's front), and its right hand lies on +X in Unity and on -X in glTF. The mirror is
// its own inverse: the same functions write a model's pose in Unity's frame (the tests' VMC
// senders). A rotation about axis a by angle θ becomes a rotation about (a.x, -a.y, -a.z) by θ:
// the mirror M = diag(-1, 1, 1) turns R into M R M, whose quaternion is (w, x, -y, -z).
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace sweepd::server {

inline glm::vec3 unity_mirrored(glm::vec3 p) { return {-p.x, p.y, p.z}; }
inline glm::quat unity_mirrored(glm::quat q) { return {q.w, q.x, -q.y, -q.z}; }

}  // namespace sweepd::server
