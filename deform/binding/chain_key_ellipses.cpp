#include "deform/binding/chain_key_ellipses.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "deform/binding/section_key_ellipse.h"

namespace sweepd::deform {

namespace {

struct RawKey {
  KeyAnchor anchor;
  glm::vec3 origin;
  glm::vec3 normal;
  PlaneFrame frame;
  KeyEllipseFit fit;      // about the section's centroid
  bool at_joint = false;  // a joint key centred on its joint, its ellipse offset to the fit
  bool usable = false;
};

glm::vec3 joint_position(std::span<const glm::mat4> world_rest, int joint) {
  return glm::vec3(world_rest[joint][3]);
}

// The in-plane unit direction closest to reference (any in-plane direction if it is normal).
glm::vec3 project_to_plane(glm::vec3 reference, glm::vec3 normal, glm::vec3 fallback) {
  glm::vec3 p = reference - glm::dot(reference, normal) * normal;
  if (glm::length(p) < 1e-6f) p = fallback - glm::dot(fallback, normal) * normal;
  return glm::normalize(p);
}

// The torso's key planes turn gradually along its chain: the bisector of the two links at each
// inner joint, the link itself at the chain's ends, mixed by the key's fraction along its link.
glm::vec3 torso_key_normal(std::span<const glm::vec3> link_direction, int joint, float fraction) {
  const int joints = static_cast<int>(link_direction.size());
  auto at_joint = [&](int j) {
    if (j <= 0 || j >= joints - 1) return link_direction[j];
    return glm::normalize(link_direction[j - 1] + link_direction[j]);
  };
  if (joint + 1 >= joints) return at_joint(joint);
  return glm::normalize(glm::mix(at_joint(joint), at_joint(joint + 1), fraction));
}

int nearest_usable(const std::vector<RawKey>& keys, int k) {
  int best = -1;
  for (int i = 0; i < static_cast<int>(keys.size()); ++i) {
    if (i == k || !keys[i].usable) continue;
    const bool better_kind =
        best < 0 || (!keys[i].anchor.is_joint_key() && keys[best].anchor.is_joint_key());
    const bool same_kind =
        best >= 0 && keys[i].anchor.is_joint_key() == keys[best].anchor.is_joint_key();
    if (better_kind || (same_kind && std::abs(i - k) < std::abs(best - k))) best = i;
  }
  return best;
}

}  // namespace

BoundSweep fit_chain_key_ellipses(std::span<const glm::vec3> positions,
                                  std::span<const std::uint32_t> indices,
                                  std::span<const glm::mat4> world_rest, BodyPart part,
                                  std::span<const int> chain, std::optional<glm::vec3> end,
                                  const BindOptions& options, glm::vec3 x_hint) {
  const int keys_per_link = options.intermediate_keys_per_link;
  const JointKeyCentre centre_rule = options.joint_key_centre;
  const std::string part_name = to_string(part);
  const int joints = static_cast<int>(chain.size());
  // The points the sweep runs through: its joints, then the carried end (if any).
  std::vector<glm::vec3> points;
  for (int j : chain) points.push_back(joint_position(world_rest, j));
  if (end) points.push_back(*end);
  const int count = static_cast<int>(points.size());
  if (count < 2)
    throw std::invalid_argument("the " + part_name +
                                " sweep needs at least two joints, or a joint and its end");
  std::vector<glm::vec3> link_direction(count);
  for (int i = 0; i + 1 < count; ++i) {
    const glm::vec3 link = points[i + 1] - points[i];
    if (glm::length(link) < 1e-5f)
      throw std::invalid_argument("the " + part_name + " sweep: joint " +
                                  std::to_string(chain[i]) + " and the " +
                                  (i + 1 < joints ? "joint " + std::to_string(chain[i + 1])
                                                  : std::string("end it carries")) +
                                  " coincide");
    link_direction[i] = glm::normalize(link);
  }
  link_direction[count - 1] = link_direction[count - 2];

  std::vector<RawKey> keys;
  for (int i = 0; i < count; ++i) {
    const int steps = i + 1 < count ? keys_per_link + 1 : 1;
    for (int s = 0; s < steps; ++s) {
      RawKey key;
      // Keys on the carried end's link, and the end's own key (fraction 1), ride the last joint.
      key.anchor.joint = chain[std::min(i, joints - 1)];
      key.anchor.next_joint = i + 1 < joints ? chain[i + 1] : -1;
      key.anchor.fraction =
          i < joints ? static_cast<float>(s) / static_cast<float>(keys_per_link + 1) : 1.0f;
      key.origin = i < joints && i + 1 < count
                       ? glm::mix(points[i], points[i + 1], key.anchor.fraction)
                       : points[i];
      key.normal = part == BodyPart::kTorso
                       ? torso_key_normal(link_direction, i, key.anchor.fraction)
                       : link_direction[i];
      key.frame = make_plane_frame(key.origin, key.normal, x_hint);
      key.fit = fit_key_ellipse(positions, indices, key.frame, key.origin);
      key.at_joint = key.anchor.is_joint_key() && centre_rule == JointKeyCentre::kAtJoint;
      if (key.fit.valid && key.anchor.is_joint_key() && centre_rule == JointKeyCentre::kAuto) {
        // The joint's radius in the centroid ellipse: inside the inner half, centre it there.
        const glm::vec2 offset = -key.fit.fit_2d.centre;
        const float c = std::cos(key.fit.fit_2d.angle), s = std::sin(key.fit.fit_2d.angle);
        const glm::vec2 local(c * offset.x + s * offset.y, -s * offset.x + c * offset.y);
        const float radius = glm::length(local / glm::vec2(key.fit.fit_2d.a, key.fit.fit_2d.b));
        key.at_joint = radius <= 0.5f;
      }
      key.usable = key.fit.valid && key.fit.closed_loop && std::isfinite(key.fit.key.a) &&
                   std::isfinite(key.fit.key.b);
      keys.push_back(key);
    }
  }

  // A joint key whose loop is far larger than its neighbours' took in another body part.
  for (int k = 0; k < static_cast<int>(keys.size()); ++k) {
    if (!keys[k].usable || !keys[k].anchor.is_joint_key()) continue;
    const int neighbour = nearest_usable(keys, k);
    if (neighbour >= 0 && !keys[neighbour].anchor.is_joint_key() &&
        keys[k].fit.fit_2d.area > kMaxJointKeyAreaRatio * keys[neighbour].fit.fit_2d.area)
      keys[k].usable = false;
  }

  // On a bone that carries an end, the keys nearest its joint may cut the body around it (the
  // OpenPose neck bone's plane at the neck base cuts the trapezius, 240-500 cm² against the
  // neck's 55-70): walking in from the end, a key far larger than the next one out took it in.
  if (end) {
    int outer = static_cast<int>(keys.size()) - 1;
    for (int k = outer - 1; k >= 0 && keys[k].anchor.joint == chain.back(); --k) {
      if (!keys[k].usable) continue;
      if (keys[outer].usable &&
          keys[k].fit.fit_2d.area > kMaxJointKeyAreaRatio * keys[outer].fit.fit_2d.area)
        keys[k].usable = false;
      else
        outer = k;
    }
  }

  BoundSweep sweep;
  sweep.part = part;
  sweep.chain.assign(chain.begin(), chain.end());
  glm::vec3 previous_x = x_hint;
  for (int k = 0; k < static_cast<int>(keys.size()); ++k) {
    const RawKey& key = keys[k];
    const bool fallback = !key.usable;
    const int source = fallback ? nearest_usable(keys, k) : k;
    if (source < 0)
      throw std::invalid_argument("cannot fit the " + part_name +
                                  " sweep: no plane orthogonal to its links cuts a closed "
                                  "cross-section of the mesh");
    const KeyEllipse& fitted = keys[source].fit.key;
    const EllipseFit& fit = keys[source].fit.fit_2d;
    const PlaneFrame& frame = key.frame;
    // A fallback takes its source's major axis onto this plane.
    const glm::vec3 major =
        project_to_plane(glm::mat3_cast(fitted.orientation)[0], frame.normal, frame.x_axis);
    const glm::vec3 minor = glm::cross(frame.normal, major);
    const glm::vec3 reference = project_to_plane(previous_x, frame.normal, major);

    KeyEllipse ellipse;
    glm::vec3 x_axis;
    if (std::abs(glm::dot(major, reference)) >= std::abs(glm::dot(minor, reference))) {
      x_axis = glm::dot(major, reference) >= 0.0f ? major : -major;
      ellipse.a = fit.a;
      ellipse.b = fit.b;
    } else {
      x_axis = glm::dot(minor, reference) >= 0.0f ? minor : -minor;
      ellipse.a = fit.b;
      ellipse.b = fit.a;
    }
    const glm::vec3 y_axis = glm::cross(frame.normal, x_axis);
    ellipse.orientation = glm::normalize(glm::quat_cast(glm::mat3(x_axis, y_axis, frame.normal)));
    ellipse.centre = fallback || key.at_joint ? key.origin : fitted.centre;
    if (!fallback && key.at_joint) {
      const glm::vec3 to_section = fitted.centre - key.origin;
      ellipse.offset = {glm::dot(to_section, x_axis), glm::dot(to_section, y_axis)};
    }
    previous_x = x_axis;

    sweep.anchors.push_back(key.anchor);
    sweep.rest_keys.push_back(ellipse);
    sweep.key_fit_errors.push_back(fallback ? 0.0f : fit.fit_error);
    sweep.key_area_ratios.push_back(fallback ? 1.0f
                                             : static_cast<float>(M_PI) * fit.a * fit.b / fit.area);
    sweep.key_fallback.push_back(fallback ? 1 : 0);
  }
  return sweep;
}

}  // namespace sweepd::deform
