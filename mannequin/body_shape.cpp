#include "mannequin/body_shape.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sweepd::mannequin {

namespace {

// Polynomial smooth minimum: min(a, b) rounded over a band of width k.
float smooth_min(float a, float b, float k) {
  const float h = std::max(k - std::abs(a - b), 0.0f) / k;
  return std::min(a, b) - h * h * k * 0.25f;
}

bool boxes_overlap(const glm::vec3& lo_a, const glm::vec3& hi_a, const glm::vec3& lo_b,
                   const glm::vec3& hi_b) {
  return glm::all(glm::lessThanEqual(lo_a, hi_b)) && glm::all(glm::lessThanEqual(lo_b, hi_a));
}

bool box_contains(const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& p) {
  return glm::all(glm::lessThanEqual(lo, p)) && glm::all(glm::lessThanEqual(p, hi));
}

}  // namespace

BodyShape::BodyShape(std::vector<BodyPart> parts, float blend_radius, float minimum_half_axis)
    : blend_radius_(blend_radius) {
  // Beyond this distance from its box a part cannot change the union's sign or fillets, even
  // for the flattest part (half-axis ratio about 1:3) whose value underestimates the distance.
  outside_value_ = std::max(0.08f, 4.0f * blend_radius);
  lower_ = glm::vec3(std::numeric_limits<float>::max());
  upper_ = glm::vec3(std::numeric_limits<float>::lowest());
  for (BodyPart& part : parts) {
    PreparedPart prepared;
    const glm::vec3 along = part.end - part.start;
    prepared.length = glm::length(along);
    prepared.axis = along / prepared.length;
    prepared.depth_axis =
        glm::normalize(part.front - glm::dot(part.front, prepared.axis) * prepared.axis);
    prepared.side_axis = glm::cross(prepared.axis, prepared.depth_axis);
    float reach = 0.0f;
    for (PartSection& section : part.sections) {
      section.side = std::max(section.side, minimum_half_axis);
      section.depth = std::max(section.depth, minimum_half_axis);
      reach =
          std::max(reach, std::max(section.side, section.depth) + std::abs(section.depth_offset));
    }
    part.start_cap = std::max(part.start_cap, minimum_half_axis);
    part.end_cap = std::max(part.end_cap, minimum_half_axis);
    const glm::vec3 tip_a = part.start - part.start_cap * prepared.axis;
    const glm::vec3 tip_b = part.end + part.end_cap * prepared.axis;
    const glm::vec3 box_lo = glm::min(tip_a, tip_b) - reach;
    const glm::vec3 box_hi = glm::max(tip_a, tip_b) + reach;
    lower_ = glm::min(lower_, box_lo - blend_radius);
    upper_ = glm::max(upper_, box_hi + blend_radius);
    prepared.reach_lower = box_lo - outside_value_;
    prepared.reach_upper = box_hi + outside_value_;
    prepared.part = std::move(part);
    all_parts_.push_back(static_cast<int>(parts_.size()));
    parts_.push_back(std::move(prepared));
  }
}

PartSection BodyShape::section_at(const PreparedPart& part, float t) const {
  const std::vector<PartSection>& sections = part.part.sections;
  if (t <= sections.front().t) return sections.front();
  if (t >= sections.back().t) return sections.back();
  std::size_t i = 1;
  while (sections[i].t < t) ++i;
  // Cubic Hermite between sections i-1 and i with Catmull-Rom slopes (flat at both ends):
  // smooth through every section, so the surface shows no rings where sections sit.
  const std::size_t a = i - 1, b = i;
  const float width = sections[b].t - sections[a].t;
  const float s = (t - sections[a].t) / width;
  const float h00 = (1.0f + 2.0f * s) * (1.0f - s) * (1.0f - s), h10 = s * (1.0f - s) * (1.0f - s);
  const float h01 = s * s * (3.0f - 2.0f * s), h11 = s * s * (s - 1.0f);
  auto interpolate = [&](float PartSection::*field) {
    auto slope = [&](std::size_t k) {
      if (k == 0 || k + 1 == sections.size()) return 0.0f;
      return (sections[k + 1].*field - sections[k - 1].*field) /
             (sections[k + 1].t - sections[k - 1].t);
    };
    return h00 * sections[a].*field + h10 * width * slope(a) + h01 * sections[b].*field +
           h11 * width * slope(b);
  };
  return {t, interpolate(&PartSection::side), interpolate(&PartSection::depth),
          interpolate(&PartSection::depth_offset)};
}

float BodyShape::prepared_value(const PreparedPart& part, const glm::vec3& p) const {
  const glm::vec3 d = p - part.part.start;
  const float s = glm::dot(d, part.axis);
  const PartSection section = section_at(part, s / part.length);
  const float x = glm::dot(d, part.side_axis) / section.side;
  const float y = (glm::dot(d, part.depth_axis) - section.depth_offset) / section.depth;
  float a = 0.0f;
  if (s < 0.0f) a = s / part.part.start_cap;
  if (s > part.length) a = (s - part.length) / part.part.end_cap;
  // The smallest half-axis turns the ellipsoidal "radius" into metres without overestimating;
  // it includes both caps so the value stays continuous where the caps begin.
  const float scale =
      std::min({section.side, section.depth, part.part.start_cap, part.part.end_cap});
  return (std::sqrt(a * a + x * x + y * y) - 1.0f) * scale;
}

float BodyShape::part_value(int part, const glm::vec3& p) const {
  return prepared_value(parts_[part], p);
}

float BodyShape::union_value(std::span<const int> parts, const glm::vec3& p) const {
  bool any = false;
  float value = outside_value_;
  for (int i : parts) {
    const PreparedPart& part = parts_[i];
    if (!box_contains(part.reach_lower, part.reach_upper, p)) continue;
    const float v = prepared_value(part, p);
    value = any ? smooth_min(value, v, blend_radius_) : v;
    any = true;
  }
  return value;
}

float BodyShape::value(const glm::vec3& p) const { return union_value(all_parts_, p); }

glm::vec3 BodyShape::gradient(const glm::vec3& p, float h) const {
  const glm::vec3 dx(h, 0, 0), dy(0, h, 0), dz(0, 0, h);
  return glm::vec3(value(p + dx) - value(p - dx), value(p + dy) - value(p - dy),
                   value(p + dz) - value(p - dz)) /
         (2.0f * h);
}

PartCoordinates BodyShape::part_coordinates(int index, const glm::vec3& p) const {
  const PreparedPart& part = parts_[index];
  const glm::vec3 d = p - part.part.start;
  const float s = glm::dot(d, part.axis);
  const float total = part.part.start_cap + part.length + part.part.end_cap;
  PartCoordinates coordinates;
  coordinates.axial = std::clamp((s + part.part.start_cap) / total, 0.0f, 1.0f);
  const float angle = std::atan2(glm::dot(d, part.side_axis), glm::dot(d, part.depth_axis));
  coordinates.angle =
      std::clamp((angle + std::numbers::pi_v<float>) / (2.0f * std::numbers::pi_v<float>), 0.0f,
                 std::nextafter(1.0f, 0.0f));
  return coordinates;
}

bool BodyShape::evaluate_block(const glm::vec3& lo, const glm::vec3& hi,
                               std::span<const glm::vec3> points, std::span<float> values) const {
  std::vector<int> near;
  for (int i = 0; i < part_count(); ++i)
    if (boxes_overlap(lo, hi, parts_[i].reach_lower, parts_[i].reach_upper)) near.push_back(i);
  if (near.empty()) return false;
  for (std::size_t k = 0; k < points.size(); ++k) values[k] = union_value(near, points[k]);
  return true;
}

}  // namespace sweepd::mannequin
