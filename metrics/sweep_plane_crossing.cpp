#include "metrics/sweep_plane_crossing.h"

#include <algorithm>
#include <limits>

#include "deform/binding/rest_sweep.h"
#include "deform/binding/sweep_coordinates.h"

namespace sweepd::metrics {

namespace {

// f by central differences of point(t) over t ± 2e-4 against normal(t).
template <typename Point, typename Normal>
double central_forward_speed(const deform::SweepCoordinate& coordinate, const Point& point,
                             const Normal& normal) {
  constexpr float kStep = 2e-4f;  // in t: small against a key span, large against float noise
  deform::SweepCoordinate before = coordinate, after = coordinate;
  before.t -= kStep;
  after.t += kStep;
  const glm::dvec3 travel = glm::dvec3(point(after)) - glm::dvec3(point(before));
  return glm::dot(glm::dvec3(normal(coordinate.t)), travel) / (2.0 * kStep);
}

}  // namespace

double forward_speed(const deform::Sweep& sweep, const deform::SweepCoordinate& coordinate) {
  return central_forward_speed(
      coordinate,
      [&](const deform::SweepCoordinate& c) { return deform::evaluate_point(sweep, c); },
      [&](float t) { return sweep.normal(t); });
}

double forward_speed(const deform::SweepPoser& posed, int sweep,
                     const deform::SweepCoordinate& coordinate) {
  return central_forward_speed(
      coordinate, [&](const deform::SweepCoordinate& c) { return posed.reference_point(sweep, c); },
      [&](float t) { return posed.reference_normal(sweep, t); });
}

PlaneCrossingMeter::PlaneCrossingMeter(const deform::BoundModel& bound)
    : bound_(bound), rest_speed_(bound.vertices.size()) {
  std::vector<deform::Sweep> rest;
  for (const deform::BoundSweep& sweep : bound.sweeps)
    rest.push_back(deform::rest_sweep(sweep, bound.options));
  for (std::size_t v = 0; v < bound.vertices.size(); ++v) {
    const deform::VertexBinding& vb = bound.vertices[v];
    for (int k = 0; k < deform::kSweepsPerVertex; ++k)
      rest_speed_[v][k] = vb.sweep[k] >= 0 && vb.weight[k] != 0.0f
                              ? forward_speed(rest[vb.sweep[k]], vb.coordinate[k])
                              : 0.0;
  }
}

std::vector<double> PlaneCrossingMeter::speed_ratios(const deform::SweepPoser& posed) const {
  std::vector<double> ratios(bound_.vertices.size(), 1.0);
  for (std::size_t v = 0; v < bound_.vertices.size(); ++v) {
    const deform::VertexBinding& vb = bound_.vertices[v];
    for (int k = 0; k < deform::kSweepsPerVertex; ++k) {
      if (vb.sweep[k] < 0 || vb.weight[k] == 0.0f || rest_speed_[v][k] == 0.0) continue;
      ratios[v] = std::min(ratios[v],
                           forward_speed(posed, vb.sweep[k], vb.coordinate[k]) / rest_speed_[v][k]);
    }
  }
  return ratios;
}

double PlaneCrossingMeter::least_rest_speed() const {
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t v = 0; v < bound_.vertices.size(); ++v)
    for (int k = 0; k < deform::kSweepsPerVertex; ++k)
      if (bound_.vertices[v].sweep[k] >= 0 && bound_.vertices[v].weight[k] != 0.0f)
        least = std::min(least, rest_speed_[v][k]);
  return least;
}

}  // namespace sweepd::metrics
