#include "metrics/quality_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "deform/binding/cross_section.h"
#include "deform/binding/rest_sweep.h"
#include "deform/mesh/mesh_topology.h"
#include "deform/sweep/swept_volume.h"

namespace sweepd::metrics {

using namespace deform;  // the metrics measure the deform library's types
namespace {

bool is_limb(BodyPart part) {
  return part == BodyPart::kLeftArm || part == BodyPart::kRightArm || part == BodyPart::kLeftLeg ||
         part == BodyPart::kRightLeg;
}

double polygon_area(std::span<const glm::vec2> points) {
  double twice = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::vec2& p = points[i];
    const glm::vec2& q = points[(i + 1) % points.size()];
    twice += static_cast<double>(p.x) * q.y - static_cast<double>(q.x) * p.y;
  }
  return 0.5 * std::abs(twice);
}

// Möller–Trumbore: does the segment p→q cross triangle (a, b, c)?
bool segment_crosses(const glm::vec3& p, const glm::vec3& q, const glm::vec3& a, const glm::vec3& b,
                     const glm::vec3& c) {
  const glm::vec3 dir = q - p, e1 = b - a, e2 = c - a;
  const glm::vec3 h = glm::cross(dir, e2);
  const float det = glm::dot(e1, h);
  if (std::abs(det) < 1e-12f) return false;  // parallel or coplanar
  const float inv = 1.0f / det;
  const glm::vec3 s = p - a;
  const float u = inv * glm::dot(s, h);
  if (u < 0.0f || u > 1.0f) return false;
  const glm::vec3 qv = glm::cross(s, e1);
  const float v = inv * glm::dot(dir, qv);
  if (v < 0.0f || u + v > 1.0f) return false;
  const float t = inv * glm::dot(e2, qv);
  return t >= 0.0f && t <= 1.0f;
}

// Whether all of y lies strictly on one side of x's plane (then they cannot cross).
bool one_side_of_plane(const std::array<glm::vec3, 3>& x, const std::array<glm::vec3, 3>& y) {
  const glm::vec3 n = glm::cross(x[1] - x[0], x[2] - x[0]);
  const float d0 = glm::dot(n, y[0] - x[0]), d1 = glm::dot(n, y[1] - x[0]),
              d2 = glm::dot(n, y[2] - x[0]);
  return (d0 > 0.0f && d1 > 0.0f && d2 > 0.0f) || (d0 < 0.0f && d1 < 0.0f && d2 < 0.0f);
}

bool triangles_cross(const std::array<glm::vec3, 3>& x, const std::array<glm::vec3, 3>& y) {
  if (one_side_of_plane(x, y) || one_side_of_plane(y, x)) return false;
  for (int e = 0; e < 3; ++e) {
    if (segment_crosses(x[e], x[(e + 1) % 3], y[0], y[1], y[2])) return true;
    if (segment_crosses(y[e], y[(e + 1) % 3], x[0], x[1], x[2])) return true;
  }
  return false;
}

}  // namespace

float section_parameter(int section) {
  return 0.1f + 0.8f * static_cast<float>(section) / (QualityMeter::kSectionsPerLimb - 1);
}

int count_self_intersections(std::span<const glm::vec3> positions,
                             std::span<const std::uint32_t> indices,
                             std::span<const std::uint32_t> welded) {
  const std::size_t triangles = indices.size() / 3;
  if (triangles == 0) return 0;
  double edge_sum = 0.0;
  for (std::size_t t = 0; t < triangles; ++t)
    edge_sum += glm::length(positions[indices[3 * t + 1]] - positions[indices[3 * t]]);
  const float cell = static_cast<float>(2.0 * edge_sum / triangles) + 1e-9f;
  std::vector<glm::ivec3> lo(triangles), hi(triangles);
  std::vector<glm::vec3> box_min(triangles), box_max(triangles);
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  auto key = [](glm::ivec3 c) {
    return (static_cast<std::uint64_t>(c.x & 0x1fffff) << 42) |
           (static_cast<std::uint64_t>(c.y & 0x1fffff) << 21) |
           static_cast<std::uint64_t>(c.z & 0x1fffff);
  };
  for (std::size_t t = 0; t < triangles; ++t) {
    glm::vec3 mn(1e30f), mx(-1e30f);
    for (int k = 0; k < 3; ++k) {
      mn = glm::min(mn, positions[indices[3 * t + k]]);
      mx = glm::max(mx, positions[indices[3 * t + k]]);
    }
    box_min[t] = mn, box_max[t] = mx;
    lo[t] = glm::ivec3(glm::floor(mn / cell));
    hi[t] = glm::ivec3(glm::floor(mx / cell));
    for (int x = lo[t].x; x <= hi[t].x; ++x)
      for (int y = lo[t].y; y <= hi[t].y; ++y)
        for (int z = lo[t].z; z <= hi[t].z; ++z)
          grid[key({x, y, z})].push_back(static_cast<std::uint32_t>(t));
  }
  int count = 0;
  for (const auto& [cell_key, members] : grid) {
    for (std::size_t i = 0; i < members.size(); ++i)
      for (std::size_t j = i + 1; j < members.size(); ++j) {
        const std::uint32_t a = members[i], b = members[j];
        const glm::ivec3 first = glm::max(lo[a], lo[b]);  // the pair's first shared cell
        if (glm::any(glm::greaterThan(first, glm::min(hi[a], hi[b])))) continue;
        if (key(first) != cell_key) continue;  // counted in that cell
        if (glm::any(glm::greaterThan(box_min[a], box_max[b])) ||
            glm::any(glm::greaterThan(box_min[b], box_max[a])))
          continue;  // the bounds do not overlap
        bool shared = false;
        for (int p = 0; p < 3 && !shared; ++p)
          for (int q = 0; q < 3 && !shared; ++q)
            shared = welded[indices[3 * a + p]] == welded[indices[3 * b + q]];
        if (shared) continue;
        const std::array<glm::vec3, 3> x{positions[indices[3 * a]], positions[indices[3 * a + 1]],
                                         positions[indices[3 * a + 2]]};
        const std::array<glm::vec3, 3> y{positions[indices[3 * b]], positions[indices[3 * b + 1]],
                                         positions[indices[3 * b + 2]]};
        if (triangles_cross(x, y)) ++count;
      }
  }
  return count;
}

double largest_distance(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  double worst = 0.0;
  for (std::size_t v = 0; v < a.size() && v < b.size(); ++v)
    worst = std::max(worst, static_cast<double>(glm::length(a[v] - b[v])));
  return worst;
}

std::vector<std::uint32_t> welded_edges(std::span<const std::uint32_t> indices,
                                        std::span<const std::uint32_t> welded) {
  std::vector<std::uint32_t> edges;
  std::unordered_set<std::uint64_t> seen;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = indices[t + k], q = indices[t + (k + 1) % 3];
      const std::uint64_t a = welded[p], b = welded[q];
      if (!seen.insert(std::min(a, b) << 32 | std::max(a, b)).second) continue;
      edges.push_back(p);
      edges.push_back(q);
    }
  return edges;
}

QualityMeter::QualityMeter(const BoundModel& bound) : bound_(bound), regions_(bound) {
  const Model& model = bound.model;
  welded_ = weld_coincident_positions(model.positions, &welded_count_);
  for (std::uint32_t i : model.indices) welded_indices_.push_back(welded_[i]);
  const std::vector<glm::vec3> rest_welded = welded_positions(model.positions);
  edges_ = welded_edges(model.indices, welded_);
  for (std::size_t e = 0; 2 * e < edges_.size(); ++e)
    rest_edge_length_.push_back(
        glm::length(model.positions[edges_[2 * e]] - model.positions[edges_[2 * e + 1]]));
  for (std::size_t s = 0; s < bound.sweeps.size(); ++s) {
    rest_mesh_volume_.push_back(regions_.volume(static_cast<int>(s), model.positions));
    const Sweep rest = rest_sweep(bound.sweeps[s], bound.options);
    rest_sweep_volume_.push_back(sweep_volume(rest));
    if (!is_limb(bound.sweeps[s].part)) continue;
    limb_sweeps_.push_back(static_cast<int>(s));
    for (int i = 0; i < kSectionsPerLimb; ++i) {
      const float t = section_parameter(i);
      const CrossSection section =
          cross_section(rest_welded, welded_indices_,
                        make_plane_frame(rest.centre(t), rest.normal(t)), rest.centre(t));
      rest_section_area_.push_back(section.found && section.closed ? polygon_area(section.points_2d)
                                                                   : 0.0);
    }
  }
}

std::vector<glm::vec3> QualityMeter::welded_positions(std::span<const glm::vec3> positions) const {
  std::vector<glm::vec3> welded(welded_count_);
  for (std::size_t v = 0; v < positions.size(); ++v) welded[welded_[v]] = positions[v];
  return welded;
}

QualityMetrics QualityMeter::measure(std::span<const glm::vec3> positions, const SweepPoser& posed,
                                     bool sweep_method) const {
  QualityMetrics metrics;
  for (std::size_t s = 0; s < bound_.sweeps.size(); ++s) {
    PartMetrics part;
    part.part = bound_.sweeps[s].part;
    if (rest_mesh_volume_[s] != 0.0)
      part.mesh_volume_change =
          regions_.volume(static_cast<int>(s), positions) / rest_mesh_volume_[s] - 1.0;
    if (sweep_method && rest_sweep_volume_[s] != 0.0)
      part.sweep_volume_change =
          sweep_volume(posed.sweep(static_cast<int>(s))) / rest_sweep_volume_[s] - 1.0;
    metrics.parts.push_back(part);
  }
  const std::vector<glm::vec3> welded = welded_positions(positions);
  for (std::size_t l = 0; l < limb_sweeps_.size(); ++l) {
    const Sweep& sweep = posed.sweep(limb_sweeps_[l]);
    for (int i = 0; i < kSectionsPerLimb; ++i) {
      const double rest_area = rest_section_area_[l * kSectionsPerLimb + i];
      if (rest_area <= 0.0) continue;
      const float t = section_parameter(i);
      const CrossSection section =
          cross_section(welded, welded_indices_, make_plane_frame(sweep.centre(t), sweep.normal(t)),
                        sweep.centre(t));
      const double area = section.found && section.closed ? polygon_area(section.points_2d) : 0.0;
      metrics.smallest_section_ratio = std::min(metrics.smallest_section_ratio, area / rest_area);
    }
  }
  metrics.self_intersections = count_self_intersections(positions, bound_.model.indices, welded_);
  std::tie(metrics.shortest_edge_ratio, metrics.longest_edge_ratio) = edge_ratio_range(positions);
  return metrics;
}

double QualityMeter::largest_edge_stretch(std::span<const glm::vec3> positions) const {
  double largest = 0.0;
  for (std::size_t e = 0; e < rest_edge_length_.size(); ++e)
    largest = std::max(largest, std::abs(edge_ratio(positions, e) - 1.0));
  return largest;
}

std::pair<double, double> QualityMeter::edge_ratio_range(
    std::span<const glm::vec3> positions) const {
  std::pair<double, double> range{1.0, 1.0};
  for (std::size_t e = 0; e < rest_edge_length_.size(); ++e) {
    const double ratio = edge_ratio(positions, e);
    range = {std::min(range.first, ratio), std::max(range.second, ratio)};
  }
  return range;
}

double QualityMeter::edge_ratio(std::span<const glm::vec3> positions, std::size_t e) const {
  if (rest_edge_length_[e] <= 0.0f) return 1.0;
  const float length = glm::length(positions[edges_[2 * e]] - positions[edges_[2 * e + 1]]);
  return static_cast<double>(length / rest_edge_length_[e]);
}

}  // namespace sweepd::metrics
