#include "deform/posing/key_posing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "deform/sweep/interpolating_splines.h"

namespace sweepd::deform {

namespace {

// An inner joint key's mitre in a pose: how much its half-axes would stretch, (a, b) factors
// (1 for none), and the bend's direction (towards the inside of the bend) on its (a, b) axes.
struct Mitre {
  glm::vec2 factor{1.0f};
  glm::vec2 inner{0.0f};
};
Mitre mitre_factors(const KeyEllipse& rest, const glm::quat& upper_turn,
                    const glm::quat& lower_turn, const glm::quat& turn) {
  const glm::vec3 rest_normal = rest.orientation * glm::vec3(0, 0, 1);
  const glm::vec3 upper = upper_turn * rest_normal, lower = lower_turn * rest_normal;
  const float stretch = mitre_stretch(upper, lower);
  // The bend's direction in the posed key's plane, taken back to the rest key's axes.
  glm::vec3 along = glm::inverse(turn) * (lower - upper);
  along -= glm::dot(along, rest_normal) * rest_normal;
  const float length = glm::length(along);
  if (stretch <= 1.0f || length < 1e-6f) return {};
  along /= length;
  const float grow = stretch * stretch - 1.0f;
  const float on_a = glm::dot(along, rest.orientation * glm::vec3(1, 0, 0));
  const float on_b = glm::dot(along, rest.orientation * glm::vec3(0, 1, 0));
  return {{std::sqrt(1.0f + grow * on_a * on_a), std::sqrt(1.0f + grow * on_b * on_b)},
          {on_a, on_b}};
}

// Whether the links meeting at chain joint `joint` (from the chain joint before it, and on to
// `next`) are further from straight in the pose than at rest. Straightening a joint the rest
// pose bends (the shared male's elbows, 46°) cuts no mitre: its rest key already has the
// bent joint's section, and growing it inflated the arm by 2.4 % when the clip's T-pose
// straightened the elbows.
// The next point is the next chain joint's position, or past the chain's last joint the next
// key's centre on the end its bone carries.
bool bends_further_than_at_rest(std::span<const int> chain, int joint, glm::vec3 rest_next,
                                glm::vec3 pose_next, std::span<const glm::vec3> rest_joint,
                                std::span<const glm::vec3> pose_joint) {
  const auto at = std::find(chain.begin(), chain.end(), joint);
  if (at == chain.begin() || at == chain.end()) return false;
  const int previous = *(at - 1);
  auto straightness = [&](std::span<const glm::vec3> p, glm::vec3 next) {
    return glm::dot(glm::normalize(p[joint] - p[previous]), glm::normalize(next - p[joint]));
  };
  return straightness(pose_joint, pose_next) < straightness(rest_joint, rest_next);
}

// Stretches key k's ellipse along the outside of the bend only: its half-axes grow by half of
// what the mitre stretches them, and its offset (KeyEllipse::offset) moves the other half away
// from the inside, so the inner side stays where it was and the outer side reaches as far as
// the mitre's. (Stretched both ways, the inner side passes the bend's centre, where the sweep
// runs backwards through itself: the integral counts that fold negatively while the mesh
// hardly resolves it, and the shared male's arm region then differs from the integral by 8.9
// points at a 150° elbow turn.) The change goes into key k's control values of a(t), b(t) and
// the offsets (Sweep's quadratic B-splines through the keys' values): only the keys k-1..k+1
// change, by that control's basis function (`spread`), so the curves change only where that
// basis function lives (up to halfway to keys k±2).
void grow_outside_of_bend(std::span<const KeyEllipse> rest, int k, const Mitre& mitre,
                          const std::array<float, 3>& spread, std::span<KeyEllipse> keys) {
  const glm::vec2 control_growth = 0.5f * (mitre.factor - 1.0f) * glm::vec2(rest[k].a, rest[k].b);
  const glm::vec2 control_shift = -glm::sign(mitre.inner) * control_growth;
  const int count = static_cast<int>(rest.size());
  for (int i = std::max(0, k - 1); i <= std::min(count - 1, k + 1); ++i) {
    const float weight = spread[i - k + 1];
    keys[i].a += weight * control_growth.x;
    keys[i].b += weight * control_growth.y;
    keys[i].offset += weight * control_shift;
  }
}

// The torso's key centres laid along its own centre line (key_posing.h): each key its rest
// spacing on from the one before, turned halfway between the two keys' turns, then the gap left
// at the last key (where its joint carries it) shared out by rest length.
void lay_centres_along_the_column(std::span<const KeyEllipse> rest, std::span<KeyEllipse> keys) {
  const int count = static_cast<int>(keys.size());
  float total = 0.0f;
  for (int k = 1; k < count; ++k) total += glm::length(rest[k].centre - rest[k - 1].centre);
  if (count < 2 || !(total > 0.0f)) return;
  const glm::vec3 end = keys[count - 1].centre;
  auto turn_of = [&](int k) { return keys[k].orientation * glm::conjugate(rest[k].orientation); };
  glm::quat previous = turn_of(0);
  for (int k = 1; k < count; ++k) {
    const glm::quat turn = turn_of(k);
    keys[k].centre =
        keys[k - 1].centre + halfway(previous, turn) * (rest[k].centre - rest[k - 1].centre);
    previous = turn;
  }
  const glm::vec3 gap = end - keys[count - 1].centre;
  float run = 0.0f;
  for (int k = 1; k < count; ++k) {
    run += glm::length(rest[k].centre - rest[k - 1].centre);
    keys[k].centre += (run / total) * gap;
  }
}

// The turn of the joint key at joint j of `sweep`: halfway between its upper and its lower
// link, except at the torso's first joint (the hips), whose parent, where it has one, is no part
// of the body (key_posing.h).
glm::quat joint_key_turn(const BoundSweep& sweep, const Skeleton& skeleton,
                         std::span<const glm::quat> joint_rotation, int j) {
  const int parent = skeleton.joints[j].parent;
  const bool below_the_body = sweep.part == BodyPart::kTorso && j == sweep.chain.front();
  return parent >= 0 && !below_the_body ? halfway(joint_rotation[parent], joint_rotation[j])
                                        : joint_rotation[j];
}

}  // namespace

glm::quat halfway(const glm::quat& a, const glm::quat& b) {
  const glm::quat b_near = glm::dot(a, b) < 0.0f ? -b : b;
  return glm::normalize(a + b_near);  // slerp(a, b, 0.5) exactly: the bisector of the arc
}

float mitre_stretch(const glm::vec3& upper_normal, const glm::vec3& lower_normal) {
  const float cos_half =
      std::sqrt(std::max(0.0f, 0.5f * (1.0f + glm::dot(upper_normal, lower_normal))));
  return 1.0f / std::max(cos_half, 1.0f / kLargestMitreStretch);
}

std::vector<std::array<float, 3>> mitre_spread(const BoundSweep& sweep) {
  const int count = static_cast<int>(sweep.rest_keys.size());
  std::vector<std::array<float, 3>> spread(count, {0.0f, 1.0f, 0.0f});
  std::vector<glm::vec3> centres(count);
  std::vector<double> t(count);
  for (int k = 0; k < count; ++k) centres[k] = sweep.rest_keys[k].centre;
  if (count < 2 || !chord_length_parameters(centres, t)) return spread;  // Sweep refuses these
  InterpolatingQuadraticSpline half_axes;
  half_axes.set_parameters(t);
  std::array<double, InterpolatingQuadraticSpline::kMaxDegree + 1> basis{};
  for (int k = 0; k < count; ++k) {
    auto basis_k_at = [&](int site) {
      const int first = half_axes.nonzero_basis(t[site], basis);
      const int r = k - first;
      return r >= 0 && r <= half_axes.degree() ? static_cast<float>(basis[r]) : 0.0f;
    };
    const float at_k = basis_k_at(k);
    spread[k] = {0.0f, 0.0f, 0.0f};
    if (at_k <= 0.0f) continue;
    for (int i = std::max(0, k - 1); i <= std::min(count - 1, k + 1); ++i)
      spread[k][i - k + 1] = basis_k_at(i) / at_k;
  }
  return spread;
}

void pose_key_ellipses(const BoundSweep& sweep, std::span<const std::array<float, 3>> spread,
                       const Skeleton& skeleton, std::span<const glm::quat> joint_rotation,
                       std::span<const glm::vec3> rest_joint, std::span<const glm::vec3> pose_joint,
                       std::span<KeyEllipse> keys) {
  const int count = static_cast<int>(sweep.rest_keys.size());
  for (int k = 0; k < count; ++k) {
    const KeyAnchor& anchor = sweep.anchors[k];
    const int j = anchor.joint;
    const KeyEllipse& rest = sweep.rest_keys[k];
    const glm::quat turn = anchor.is_joint_key()
                               ? joint_key_turn(sweep, skeleton, joint_rotation, j)
                               : joint_rotation[j];
    glm::quat orientation_turn = turn;
    const bool column = sweep.part == BodyPart::kNeck || sweep.part == BodyPart::kTorso;
    if (column && !anchor.is_joint_key()) {
      // On a neck bone that carries the head, towards the head's own turn (the bone's).
      const glm::quat from = joint_key_turn(sweep, skeleton, joint_rotation, j);
      const glm::quat to = anchor.next_joint >= 0
                               ? joint_key_turn(sweep, skeleton, joint_rotation, anchor.next_joint)
                               : joint_rotation[j];
      orientation_turn = glm::slerp(from, glm::dot(from, to) < 0.0f ? -to : to, anchor.fraction);
    }
    KeyEllipse& posed = keys[k];
    posed.centre = pose_joint[j] + turn * (rest.centre - rest_joint[j]);
    posed.orientation = glm::normalize(orientation_turn * rest.orientation);
    posed.a = rest.a;
    posed.b = rest.b;
    posed.offset = rest.offset;  // in the key's own frame: it turns with the key
  }
  if (sweep.part == BodyPart::kTorso) lay_centres_along_the_column(sweep.rest_keys, keys);
  // Mitres, once every key is posed: each spreads into its neighbours.
  for (int k = 0; k < count; ++k) {
    const KeyAnchor& anchor = sweep.anchors[k];
    const int j = anchor.joint;
    const int parent = skeleton.joints[j].parent;
    // The chain's last joint bends like an inner one where its bone carries an end on to it.
    const bool inner =
        anchor.next_joint >= 0 || (k + 1 < count && sweep.anchors[k + 1].is_on_carried_end());
    if (!anchor.is_joint_key() || parent < 0 || j == sweep.chain.front() || !inner) continue;
    const glm::vec3 rest_next =
        anchor.next_joint >= 0 ? rest_joint[anchor.next_joint] : sweep.rest_keys[k + 1].centre;
    const glm::vec3 pose_next =
        anchor.next_joint >= 0 ? pose_joint[anchor.next_joint] : keys[k + 1].centre;
    if (!bends_further_than_at_rest(sweep.chain, j, rest_next, pose_next, rest_joint, pose_joint))
      continue;
    const Mitre mitre = mitre_factors(sweep.rest_keys[k], joint_rotation[parent], joint_rotation[j],
                                      joint_key_turn(sweep, skeleton, joint_rotation, j));
    if (mitre.factor != glm::vec2(1.0f))
      grow_outside_of_bend(sweep.rest_keys, k, mitre, spread[k], keys);
  }
}

}  // namespace sweepd::deform
