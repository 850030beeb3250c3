#include "metrics/region_quality.h"

#include <algorithm>

namespace sweepd::metrics {

using namespace deform;  // the metrics measure the deform library's types

SkinningComparison compare_with_skinning(const RegionFigures& sweep, const RegionFigures& lbs,
                                         const RegionFigures& dqs) {
  SkinningComparison c;
  if (!sweep.swept) return c;
  c.swept = true;
  c.sweep = sweep.swept_stretch;
  c.baseline = std::min(lbs.swept_stretch, dqs.swept_stretch);
  c.excess = c.sweep / (kSkinningTolerance * c.baseline);
  c.worse = c.excess > 1.0 || sweep.swept_flipped > std::min(lbs.swept_flipped, dqs.swept_flipped);
  return c;
}

std::array<int, 2> edge_regions(int region_a, int region_b) {
  return {region_a, region_b == region_a ? -1 : region_b};
}

std::array<int, 3> triangle_regions(int region_a, int region_b, int region_c) {
  return {region_a, region_b == region_a ? -1 : region_b,
          region_c == region_a || region_c == region_b ? -1 : region_c};
}

std::vector<glm::mat3> joint_turns(std::span<const glm::mat4> joint_world,
                                   std::span<const glm::mat4> inverse_rest) {
  std::vector<glm::mat3> turn(inverse_rest.size());
  for (std::size_t j = 0; j < turn.size(); ++j)
    turn[j] = glm::mat3(joint_world[j] * inverse_rest[j]);
  return turn;
}

RegionLabels label_regions(const BoundModel& bound) {
  const Model& model = bound.model;
  const std::vector<BodyPart> part_of = label_joints(bound.rig, model.skeleton);
  std::vector<int> index_of_part(static_cast<int>(BodyPart::kRightFoot) + 1, -1);
  std::vector<BodyPart> vertex_part(model.vertex_count());
  RegionLabels labels;
  for (std::size_t v = 0; v < vertex_part.size(); ++v) {
    labels.strongest_joint.push_back(model.strongest_joint(v));
    const BodyPart part = part_of[labels.strongest_joint.back()];
    vertex_part[v] = part == BodyPart::kNone ? BodyPart::kTorso : part;
    index_of_part[static_cast<int>(vertex_part[v])] = 0;
  }
  for (std::size_t p = 0; p < index_of_part.size(); ++p)
    if (index_of_part[p] == 0) {
      index_of_part[p] = static_cast<int>(labels.regions.size());
      labels.regions.push_back(static_cast<BodyPart>(p));
    }
  for (const BodyPart part : vertex_part)
    labels.region_of_vertex.push_back(index_of_part[static_cast<int>(part)]);
  return labels;
}

RegionMeter::RegionMeter(const BoundModel& bound) : bound_(bound), quality_(bound), crease_(bound) {
  const Model& model = bound.model;
  RegionLabels labels = label_regions(bound);
  regions_ = std::move(labels.regions);
  region_of_vertex_ = std::move(labels.region_of_vertex);
  strongest_joint_ = std::move(labels.strongest_joint);
  for (const VertexBinding& binding : bound.vertices) swept_.push_back(binding.skin_weight < 1.0f);
  for (const glm::mat4& world : model.skeleton.world_rest_matrices())
    inverse_rest_.push_back(glm::inverse(world));
  for (std::size_t t = 0; 3 * t + 2 < model.indices.size(); ++t)
    rest_normal_.push_back(triangle_normal(model.positions, model.indices, t));
}

std::vector<RegionFigures> RegionMeter::measure(std::span<const glm::vec3> positions,
                                                std::span<const glm::mat4> joint_world) const {
  std::vector<RegionFigures> figures(regions_.size());
  for (std::size_t e = 0; e < quality_.edge_count(); ++e) {
    const auto [a, b] = quality_.edge_vertices(e);
    const double ratio = quality_.edge_ratio(positions, e);
    for (const int region : edge_regions(region_of_vertex(a), region_of_vertex(b))) {
      if (region < 0) continue;
      RegionFigures& f = figures[region];
      f.stretch = std::max(f.stretch, ratio);
      f.squash = std::min(f.squash, ratio);
      if (swept_[a] || swept_[b]) {
        f.swept = true;
        f.swept_stretch = std::max(f.swept_stretch, ratio);
      }
    }
  }
  for (std::size_t e = 0; e < crease_.edge_count(); ++e) {
    const auto [a, b] = crease_.edge_vertices(e);
    const double change = crease_.change_from_rest(positions, e);
    for (const int region : edge_regions(region_of_vertex(a), region_of_vertex(b)))
      if (region >= 0) figures[region].crease = std::max(figures[region].crease, change);
  }
  const std::vector<glm::mat3> joint_turn = joint_turns(joint_world, inverse_rest_);
  const std::vector<std::uint32_t>& indices = bound_.model.indices;
  for (std::size_t t = 0; t < rest_normal_.size(); ++t) {
    const std::uint32_t* corner = &indices[3 * t];
    const int corner_joint[3] = {strongest_joint_[corner[0]], strongest_joint_[corner[1]],
                                 strongest_joint_[corner[2]]};
    if (!flipped_from_rest(triangle_normal(positions, indices, t), rest_normal_[t], joint_turn,
                           corner_joint))
      continue;
    const bool swept = swept_[corner[0]] || swept_[corner[1]] || swept_[corner[2]];
    for (const int region :
         triangle_regions(region_of_vertex(corner[0]), region_of_vertex(corner[1]),
                          region_of_vertex(corner[2]))) {
      if (region < 0) continue;
      ++figures[region].flipped;
      figures[region].swept_flipped += swept;
    }
  }
  return figures;
}

}  // namespace sweepd::metrics
