#include "deform/edits/angle_driven_key_edits.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "deform/binding/bound_model.h"
#include "deform/model/joint_turn_from_rest.h"

namespace sweepd::deform {
namespace {

constexpr int kChannels = 8;  // offset xyz, rotation xyz, scale_a − 1, scale_b − 1

std::array<float, kChannels> channels(const KeyEllipseCorrection& c) {
  return {c.offset.x,   c.offset.y,   c.offset.z,       c.rotation.x,
          c.rotation.y, c.rotation.z, c.scale_a - 1.0f, c.scale_b - 1.0f};
}

KeyEllipseCorrection from_channels(const std::array<float, kChannels>& v) {
  return {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, v[6] + 1.0f, v[7] + 1.0f};
}

// The knots of an edit: the implied zero at 0°, then its samples.
float knot_angle(const KeyEllipseEdit& edit, std::size_t i) {
  return i == 0 ? 0.0f : edit.samples[i - 1].angle_degrees;
}
float knot_value(const KeyEllipseEdit& edit, std::size_t i, int channel) {
  return i == 0 ? 0.0f : channels(edit.samples[i - 1].correction)[channel];
}

// Fritsch–Butland tangent at interior knot i (monotone: 0 at a local extremum), 0 at the ends.
float tangent(const KeyEllipseEdit& edit, std::size_t i, int channel) {
  const std::size_t last = edit.samples.size();
  if (i == 0 || i == last) return 0.0f;
  const float h0 = knot_angle(edit, i) - knot_angle(edit, i - 1);
  const float h1 = knot_angle(edit, i + 1) - knot_angle(edit, i);
  const float d0 = (knot_value(edit, i, channel) - knot_value(edit, i - 1, channel)) / h0;
  const float d1 = (knot_value(edit, i + 1, channel) - knot_value(edit, i, channel)) / h1;
  if (d0 * d1 <= 0.0f) return 0.0f;
  return 3.0f * (h0 + h1) / ((2.0f * h1 + h0) / d0 + (h1 + 2.0f * h0) / d1);
}

}  // namespace

std::string validate(KeyEllipseEdits& edits, const BoundModel& bound) {
  const int joints = static_cast<int>(bound.model.skeleton.joints.size());
  for (std::size_t e = 0; e < edits.edits.size(); ++e) {
    KeyEllipseEdit& edit = edits.edits[e];
    const std::string where = "edit " + std::to_string(e) + ": ";
    if (edit.sweep < 0 || edit.sweep >= static_cast<int>(bound.sweeps.size()))
      return where + "sweep " + std::to_string(edit.sweep) + " out of range [0, " +
             std::to_string(bound.sweeps.size()) + ")";
    const int keys = static_cast<int>(bound.sweeps[edit.sweep].rest_keys.size());
    if (edit.key < 0 || edit.key >= keys)
      return where + "key " + std::to_string(edit.key) + " out of range [0, " +
             std::to_string(keys) + ")";
    if (edit.joint < 0 || edit.joint >= joints)
      return where + "joint " + std::to_string(edit.joint) + " out of range [0, " +
             std::to_string(joints) + ")";
    if (edit.samples.empty()) return where + "no samples";
    std::sort(edit.samples.begin(), edit.samples.end(),
              [](const auto& x, const auto& y) { return x.angle_degrees < y.angle_degrees; });
    for (std::size_t i = 0; i < edit.samples.size(); ++i) {
      const KeyEllipseEditSample& s = edit.samples[i];
      for (float v : channels(s.correction))
        if (!std::isfinite(v)) return where + "a non-finite correction";
      if (!std::isfinite(s.angle_degrees) || !(s.angle_degrees > 0.0f))
        return where + "angle " + std::to_string(s.angle_degrees) +
               " must be positive (the rest pose, 0 degrees, is never edited)";
      if (i > 0 && s.angle_degrees == edit.samples[i - 1].angle_degrees)
        return where + "two samples at " + std::to_string(s.angle_degrees) + " degrees";
      if (!(s.correction.scale_a > 0.0f) || !(s.correction.scale_b > 0.0f))
        return where + "scales must be positive";
    }
  }
  return {};
}

KeyEllipseCorrection correction_at(const KeyEllipseEdit& edit, float angle_degrees) {
  const std::size_t last = edit.samples.size();
  if (last == 0 || !(angle_degrees > 0.0f)) return {};
  if (angle_degrees >= knot_angle(edit, last)) return edit.samples.back().correction;
  std::size_t i = 0;
  while (knot_angle(edit, i + 1) <= angle_degrees) ++i;
  const float x0 = knot_angle(edit, i), h = knot_angle(edit, i + 1) - x0;
  const float u = (angle_degrees - x0) / h;
  const float h00 = (1 + 2 * u) * (1 - u) * (1 - u), h10 = u * (1 - u) * (1 - u);
  const float h01 = u * u * (3 - 2 * u), h11 = u * u * (u - 1);
  std::array<float, kChannels> v{};
  for (int c = 0; c < kChannels; ++c)
    v[c] = h00 * knot_value(edit, i, c) + h10 * h * tangent(edit, i, c) +
           h01 * knot_value(edit, i + 1, c) + h11 * h * tangent(edit, i + 1, c);
  return from_channels(v);
}

void apply_correction(const KeyEllipseCorrection& correction, KeyEllipse& key) {
  key.centre += glm::mat3_cast(key.orientation) * correction.offset;
  const float degrees = glm::length(correction.rotation);
  if (degrees > 0.0f)
    key.orientation = glm::normalize(
        key.orientation * glm::angleAxis(glm::radians(degrees), correction.rotation / degrees));
  key.a *= correction.scale_a;
  key.b *= correction.scale_b;
}

void apply_key_ellipse_edits(const KeyEllipseEdits& edits, const BoundModel& bound, int sweep,
                             std::span<const glm::quat> joint_rotation,
                             std::span<KeyEllipse> keys) {
  for (const KeyEllipseEdit& edit : edits.edits) {
    if (edit.sweep != sweep) continue;
    const float angle =
        glm::degrees(joint_turn_from_rest(bound.model.skeleton, joint_rotation, edit.joint));
    apply_correction(correction_at(edit, angle), keys[edit.key]);
  }
}

}  // namespace sweepd::deform
