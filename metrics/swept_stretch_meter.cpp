#include "metrics/swept_stretch_meter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

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
    for (int k = 0; k < 3; ++k) read[corner[k]] = true;
    const glm::vec3 rest_normal = triangle_normal(model.positions, model.indices, t);
    for (const int region :
         triangle_regions(labels.region_of_vertex[corner[0]], labels.region_of_vertex[corner[1]],
                          labels.region_of_vertex[corner[2]])) {
      if (region < 0) continue;  // a triangle between regions is measured in each
      for (int k = 0; k < 3; ++k) {
        triangles_.push_back(corner[k]);
        triangle_joints_.push_back(labels.strongest_joint[corner[k]]);
      }
      triangle_region_.push_back(region);
      rest_normal_.push_back(rest_normal);
    }
  }
  group_by_region();
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

namespace {

// The items' indices ordered by their region, stably.
std::vector<std::uint32_t> order_by_region(const std::vector<int>& region_of_item) {
  std::vector<std::uint32_t> order(region_of_item.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return region_of_item[a] < region_of_item[b];
  });
  return order;
}

// Per-item values (`width` of them per item) put in `order`.
template <class T>
void permute(std::vector<T>& values, const std::vector<std::uint32_t>& order,
             std::size_t width = 1) {
  std::vector<T> permuted;
  permuted.reserve(values.size());
  for (const std::uint32_t item : order)
    permuted.insert(permuted.end(), values.begin() + width * item,
                    values.begin() + width * (item + 1));
  values = std::move(permuted);
}

}  // namespace

void SweptStretchMeter::group_by_region() {
  const std::vector<std::uint32_t> edge_order = order_by_region(edge_region_);
  permute(edges_, edge_order, 2);
  permute(inverse_squared_rest_, edge_order);
  permute(edge_region_, edge_order);
  const std::vector<std::uint32_t> triangle_order = order_by_region(triangle_region_);
  permute(triangles_, triangle_order, 3);
  permute(triangle_region_, triangle_order);
  permute(triangle_joints_, triangle_order, 3);
  permute(rest_normal_, triangle_order);
  index_regions();
}

void SweptStretchMeter::index_regions() {
  auto first_of_each = [&](const std::vector<int>& region_of_item) {
    std::vector<std::uint32_t> first(regions_.size() + 1, 0);
    for (const int r : region_of_item) ++first[r + 1];
    for (std::size_t r = 0; r < regions_.size(); ++r) first[r + 1] += first[r];
    return first;
  };
  edge_first_ = first_of_each(edge_region_);
  triangle_first_ = first_of_each(triangle_region_);
}

void SweptStretchMeter::gather(std::span<const glm::vec3> positions,
                               std::vector<glm::vec3>& measured) const {
  measured.resize(vertices_.size());
  for (std::size_t i = 0; i < vertices_.size(); ++i) measured[i] = positions[vertices_[i]];
}

void SweptStretchMeter::measure(std::span<const glm::vec3> positions,
                                std::span<const glm::mat4> joint_world,
                                std::vector<RegionFigures>& figures) const {
  std::vector<int> stretched_edges;
  measure(positions, joint_world, figures, stretched_edges);
}

void SweptStretchMeter::measure(std::span<const glm::vec3> positions,
                                std::span<const glm::mat4> joint_world,
                                std::vector<RegionFigures>& figures,
                                std::vector<int>& stretched_edges) const {
  measure_sets<1>({positions}, joint_world, {&figures}, {&stretched_edges});
}

void SweptStretchMeter::measure_two(std::span<const glm::vec3> first,
                                    std::span<const glm::vec3> second,
                                    std::span<const glm::mat4> joint_world,
                                    std::vector<RegionFigures>& first_figures,
                                    std::vector<RegionFigures>& second_figures) const {
  std::vector<int> first_stretched, second_stretched;
  measure_sets<2>({first, second}, joint_world, {&first_figures, &second_figures},
                  {&first_stretched, &second_stretched});
}

template <std::size_t K>
void SweptStretchMeter::measure_sets(
    const std::array<std::span<const glm::vec3>, K>& positions,
    std::span<const glm::mat4> joint_world,
    const std::array<std::vector<RegionFigures>*, K>& figures,
    const std::array<std::vector<int>*, K>& stretched_edges) const {
  for (std::size_t k = 0; k < K; ++k) {
    figures[k]->assign(regions_.size(), RegionFigures{});
    stretched_edges[k]->assign(regions_.size(), 0);
  }
  // Region by region (the items are grouped so), the squared ratios' largest (a square root per
  // region, not per edge) and the counts in registers: the largest of a set of floats and a
  // count do not depend on the order they are taken in. Each set by the same operations.
  constexpr float kStretchedSquared = kStretchedEdge * kStretchedEdge;
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    std::array<float, K> largest;
    largest.fill(1.0f);
    std::array<int, K> stretched{};
    for (std::uint32_t e = edge_first_[r]; e < edge_first_[r + 1]; ++e) {
      for (std::size_t k = 0; k < K; ++k) {
        const float squared = squared_ratio(positions[k], e);
        largest[k] = std::max(largest[k], squared);
        stretched[k] += squared > kStretchedSquared;
      }
    }
    for (std::size_t k = 0; k < K; ++k) {
      (*figures[k])[r].swept = region_swept_[r];
      (*figures[k])[r].swept_stretch = std::sqrt(static_cast<double>(largest[k]));
      (*stretched_edges[k])[r] = stretched[k];
    }
  }
  const std::vector<glm::mat3> joint_turn = joint_turns(joint_world, inverse_rest_);
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    std::array<int, K> flipped{};
    for (std::uint32_t i = triangle_first_[r]; i < triangle_first_[r + 1]; ++i)
      for (std::size_t k = 0; k < K; ++k)
        flipped[k] += flipped_from_rest(triangle_normal(positions[k], triangles_, i),
                                        rest_normal_[i], joint_turn, &triangle_joints_[3 * i]);
    for (std::size_t k = 0; k < K; ++k) (*figures[k])[r].swept_flipped += flipped[k];
  }
}

std::optional<std::array<std::uint32_t, 2>> SweptStretchMeter::longest_edge(
    std::span<const glm::vec3> positions, int region) const {
  std::optional<std::array<std::uint32_t, 2>> longest;
  float largest = -1.0f;
  for (std::uint32_t e = edge_first_[region]; e < edge_first_[region + 1]; ++e) {
    const float squared = squared_ratio(positions, e);
    if (squared > largest) {
      largest = squared;
      longest = {vertices_[edges_[2 * e]], vertices_[edges_[2 * e + 1]]};
    }
  }
  return longest;
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
      part.triangle_joints_.insert(
          part.triangle_joints_.end(),
          {triangle_joints_[3 * t], triangle_joints_[3 * t + 1], triangle_joints_[3 * t + 2]});
      part.rest_normal_.push_back(rest_normal_[t]);
    }
  for (std::size_t i = 0; i < vertices_.size(); ++i)
    if (read[i]) {
      compact[i] = static_cast<std::uint32_t>(part.vertices_.size());
      part.vertices_.push_back(vertices_[i]);
    }
  for (std::uint32_t& v : part.edges_) v = compact[v];
  for (std::uint32_t& v : part.triangles_) v = compact[v];
  part.index_regions();  // the whole meter's order, so still grouped by region
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
