#include "metrics/swept_stretch_meter.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "deform/mesh/mesh_topology.h"
#include "metrics/quality_metrics.h"

namespace sweepd::metrics {

using namespace deform;  // the metrics measure the deform library's types

SweptStretchMeter::SweptStretchMeter(const BoundModel& bound) {
  const Model& model = bound.model;
  RegionLabels labels = label_regions(bound);
  regions_ = std::move(labels.regions);
  region_swept_.assign(regions_.size(), false);
  std::vector<bool> swept;
  for (const VertexBinding& binding : bound.vertices) swept.push_back(binding.skin_weight < 1.0f);
  // The vertices read: those of a swept edge or triangle, renumbered in ascending order.
  std::vector<bool> read(model.vertex_count(), false);
  std::size_t welded_count = 0;
  const std::vector<std::uint32_t> welded =
      weld_coincident_positions(model.positions, &welded_count);
  const std::vector<std::uint32_t> edges = welded_edges(model.indices, welded);
  for (std::size_t e = 0; 2 * e < edges.size(); ++e) {
    const std::uint32_t a = edges[2 * e], b = edges[2 * e + 1];
    if (!swept[a] && !swept[b]) continue;
    const std::array<int, 2> regions =
        edge_regions(labels.region_of_vertex[a], labels.region_of_vertex[b]);
    for (const int region : regions)
      if (region >= 0) region_swept_[region] = true;
    const glm::vec3 rest = model.positions[a] - model.positions[b];
    if (glm::dot(rest, rest) <= 0.0f) continue;  // ratio 1, as QualityMeter::edge_ratio
    read[a] = read[b] = true;
    for (const int region : regions) {  // an edge between two regions is measured in each
      if (region < 0) continue;
      edges_.push_back(a);
      edges_.push_back(b);
      inverse_squared_rest_.push_back(1.0f / glm::dot(rest, rest));
      edge_region_.push_back(region);
    }
  }
  for (std::size_t t = 0; 3 * t + 2 < model.indices.size(); ++t) {
    const std::uint32_t* corner = &model.indices[3 * t];
    if (!swept[corner[0]] && !swept[corner[1]] && !swept[corner[2]]) continue;
    for (int k = 0; k < 3; ++k) {
      triangles_.push_back(corner[k]);
      read[corner[k]] = true;
    }
    triangle_region_.push_back(labels.region_of_vertex[corner[0]]);
    triangle_joint_.push_back(labels.strongest_joint[corner[0]]);
    rest_normal_.push_back(triangle_normal(model.positions, model.indices, t));
  }
  std::vector<std::uint32_t> compact(model.vertex_count(), 0);
  for (std::uint32_t v = 0; v < model.vertex_count(); ++v)
    if (read[v]) {
      compact[v] = static_cast<std::uint32_t>(vertices_.size());
      vertices_.push_back(v);
    }
  for (std::uint32_t& v : edges_) v = compact[v];
  for (std::uint32_t& v : triangles_) v = compact[v];
  for (const glm::mat4& world : model.skeleton.world_rest_matrices())
    inverse_rest_.push_back(glm::inverse(world));
}

void SweptStretchMeter::gather(std::span<const glm::vec3> positions,
                               std::vector<glm::vec3>& measured) const {
  measured.resize(vertices_.size());
  for (std::size_t i = 0; i < vertices_.size(); ++i) measured[i] = positions[vertices_[i]];
}

void SweptStretchMeter::measure(std::span<const glm::vec3> positions,
                                std::span<const glm::mat4> joint_world,
                                std::vector<RegionFigures>& figures) const {
  measure(positions, joint_world, figures, stretched_);
}

void SweptStretchMeter::measure(std::span<const glm::vec3> positions,
                                std::span<const glm::mat4> joint_world,
                                std::vector<RegionFigures>& figures,
                                std::vector<int>& stretched_edges) const {
  figures.assign(regions_.size(), RegionFigures{});
  stretched_edges.assign(regions_.size(), 0);
  // The squared ratios' largest per region (a square root per region, not per edge).
  squared_.assign(regions_.size(), 1.0f);
  constexpr float kStretchedSquared = kStretchedEdge * kStretchedEdge;
  for (std::size_t e = 0; e < inverse_squared_rest_.size(); ++e) {
    const glm::vec3 d = positions[edges_[2 * e]] - positions[edges_[2 * e + 1]];
    const float squared = glm::dot(d, d) * inverse_squared_rest_[e];
    float& largest = squared_[edge_region_[e]];
    largest = std::max(largest, squared);
    stretched_edges[edge_region_[e]] += squared > kStretchedSquared;
  }
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    figures[r].swept = region_swept_[r];
    figures[r].swept_stretch = std::sqrt(static_cast<double>(squared_[r]));
  }
  carry_.resize(inverse_rest_.size());
  for (std::size_t j = 0; j < carry_.size(); ++j)
    carry_[j] = glm::mat3(joint_world[j] * inverse_rest_[j]);
  for (std::size_t i = 0; i < rest_normal_.size(); ++i) {
    if (glm::dot(triangle_normal(positions, triangles_, i),
                 carry_[triangle_joint_[i]] * rest_normal_[i]) < 0.0f)
      ++figures[triangle_region_[i]].swept_flipped;
  }
}

std::vector<std::uint8_t> SweptStretchMeter::regions_touched(
    std::span<const std::uint8_t> moving) const {
  std::vector<std::uint8_t> touched(regions_.size(), 0);
  for (std::size_t e = 0; e < edge_region_.size(); ++e)
    if (moving[vertices_[edges_[2 * e]]] || moving[vertices_[edges_[2 * e + 1]]])
      touched[edge_region_[e]] = 1;
  for (std::size_t t = 0; t < triangle_region_.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (moving[vertices_[triangles_[3 * t + k]]]) touched[triangle_region_[t]] = 1;
  return touched;
}

SweptStretchMeter SweptStretchMeter::part(std::span<const std::uint8_t> moving,
                                          bool touching) const {
  const std::vector<std::uint8_t> touched = regions_touched(moving);
  SweptStretchMeter part;
  part.regions_ = regions_;
  part.region_swept_ = region_swept_;
  part.inverse_rest_ = inverse_rest_;
  // Kept items' vertices renumbered in ascending model order, as the whole meter's are.
  std::vector<std::uint32_t> compact(vertices_.size(), 0);
  std::vector<bool> read(vertices_.size(), false);
  auto kept = [&](const std::uint32_t* corner, int n, int region) {
    if (!touched[region]) return false;
    bool moved = false;
    for (int k = 0; k < n; ++k) moved = moved || moving[vertices_[corner[k]]];
    if (moved != touching) return false;
    for (int k = 0; k < n; ++k) read[corner[k]] = true;
    return true;
  };
  for (std::size_t e = 0; e < inverse_squared_rest_.size(); ++e)
    if (kept(&edges_[2 * e], 2, edge_region_[e])) {
      part.edges_.insert(part.edges_.end(), {edges_[2 * e], edges_[2 * e + 1]});
      part.inverse_squared_rest_.push_back(inverse_squared_rest_[e]);
      part.edge_region_.push_back(edge_region_[e]);
    }
  for (std::size_t t = 0; t < rest_normal_.size(); ++t)
    if (kept(&triangles_[3 * t], 3, triangle_region_[t])) {
      part.triangles_.insert(part.triangles_.end(),
                             {triangles_[3 * t], triangles_[3 * t + 1], triangles_[3 * t + 2]});
      part.triangle_region_.push_back(triangle_region_[t]);
      part.triangle_joint_.push_back(triangle_joint_[t]);
      part.rest_normal_.push_back(rest_normal_[t]);
    }
  for (std::size_t i = 0; i < vertices_.size(); ++i)
    if (read[i]) {
      compact[i] = static_cast<std::uint32_t>(part.vertices_.size());
      part.vertices_.push_back(vertices_[i]);
    }
  for (std::uint32_t& v : part.edges_) v = compact[v];
  for (std::uint32_t& v : part.triangles_) v = compact[v];
  return part;
}

void SweptStretchMeter::combine(std::vector<RegionFigures>& figures,
                                std::vector<int>& stretched_edges,
                                const std::vector<RegionFigures>& other_figures,
                                const std::vector<int>& other_stretched_edges) {
  for (std::size_t r = 0; r < figures.size(); ++r) {
    figures[r].swept_stretch = std::max(figures[r].swept_stretch, other_figures[r].swept_stretch);
    figures[r].swept_flipped += other_figures[r].swept_flipped;
    stretched_edges[r] += other_stretched_edges[r];
  }
}

}  // namespace sweepd::metrics
