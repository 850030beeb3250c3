#include "deform/binding/sweep_coordinates.h"

#include <cmath>
#include <limits>

namespace sweepd::deform {

SweepPlanes sample_planes(const Sweep& sweep, int samples_per_span) {
  SweepPlanes planes;
  const auto keys = sweep.parameters();
  for (std::size_t i = 0; i + 1 < keys.size(); ++i)
    for (int s = 0; s < samples_per_span; ++s)
      planes.t.push_back(
          static_cast<float>(keys[i] + (keys[i + 1] - keys[i]) * s / samples_per_span));
  planes.t.push_back(1.0f);
  for (float t : planes.t) {
    planes.centre.push_back(sweep.centre(t));
    planes.normal.push_back(sweep.normal(t));
  }
  return planes;
}

SweepCoordinate bind_point(const Sweep& sweep, const SweepPlanes& planes, glm::vec3 point) {
  const std::size_t count = planes.t.size();
  float best_t = 0.0f;
  float best_distance = std::numeric_limits<float>::infinity();
  // R(t) and C̃(t) of the best t, kept for the coordinates below: C̃ as Sweep::ellipse_centre
  // computes it, so the same floats as evaluating both again there.
  glm::mat3 best_rotation(1.0f);
  glm::vec3 best_centre(0.0f);
  auto consider = [&](float t) {
    const glm::mat3 rotation = sweep.rotation(t);
    const glm::vec3 centre = sweep.centre(t) + rotation * glm::vec3(sweep.offset(t), 0.0f);
    const float distance = glm::length(point - centre);
    if (distance < best_distance) {
      best_distance = distance;
      best_t = t;
      best_rotation = rotation;
      best_centre = centre;
    }
  };
  float previous = glm::dot(point - planes.centre[0], planes.normal[0]);
  if (previous < 0.0f) consider(0.0f);  // before the first plane
  for (std::size_t j = 1; j < count; ++j) {
    const float current = glm::dot(point - planes.centre[j], planes.normal[j]);
    if (previous >= 0.0f && current < 0.0f) {
      const float d0 = previous, d1 = -current;
      consider((d1 * planes.t[j - 1] + d0 * planes.t[j]) / (d0 + d1));
    }
    previous = current;
  }
  if (previous >= 0.0f) consider(1.0f);               // after the last plane
  if (!std::isfinite(best_distance)) {                // unreachable for a finite point; be safe
    best_t = 0.0f;
    best_rotation = sweep.rotation(0.0f);
    best_centre = sweep.ellipse_centre(0.0f);
  }

  SweepCoordinate coordinate;
  coordinate.t = best_t;
  const glm::vec3 local = glm::transpose(best_rotation) * (point - best_centre);
  const float a = sweep.a(best_t), b = sweep.b(best_t);
  const float u = local.x / a, v = local.y / b;
  const float r = std::sqrt(u * u + v * v);
  coordinate.theta = std::atan2(v, u);
  coordinate.da = (r - 1.0f) * a;
  coordinate.db = (r - 1.0f) * b;
  coordinate.c = local.z;
  return coordinate;
}

glm::vec3 evaluate_point(const Sweep& sweep, const SweepCoordinate& coordinate) {
  const float t = coordinate.t;
  const glm::vec3 local((sweep.a(t) + coordinate.da) * std::cos(coordinate.theta),
                        (sweep.b(t) + coordinate.db) * std::sin(coordinate.theta), coordinate.c);
  return sweep.ellipse_centre(t) + sweep.rotation(t) * local;
}

}  // namespace sweepd::deform
