#include "io/bind_pose_vertices.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "io/rest_transform.h"

namespace sweepd::io {

namespace {

// The validator's criterion for normalised weights: |sum - 1| <= 2e-7 per non-zero weight.
constexpr double kWeightTolerancePerInfluence = 2e-7;

}  // namespace

void add_influence(std::vector<std::pair<int, double>>& influences, int joint, double weight) {
  auto same = std::find_if(influences.begin(), influences.end(),
                           [&](const auto& influence) { return influence.first == joint; });
  if (same != influences.end())
    same->second += weight;
  else
    influences.emplace_back(joint, weight);
}

void BindPoseVertices::append(std::vector<std::pair<int, double>>& influences, int fallback,
                              std::span<const glm::dmat4> skinning, const glm::dvec3& position,
                              const glm::dvec3* normal, const glm::vec2* uv) {
  std::array<std::uint16_t, deform::kInfluences> joints{};
  std::array<float, deform::kInfluences> weights{};
  double sum = 0.0;
  for (const auto& influence : influences) sum += influence.second;
  if (sum <= 0.0) {
    ++report_.zero_weight_vertex_count;
    fallback_used_ = fallback;
    joints[0] = static_cast<std::uint16_t>(fallback);
    weights[0] = 1.0f;
  } else {
    if (std::abs(sum - 1.0) > kWeightTolerancePerInfluence * influences.size()) {
      ++report_.renormalised_weight_count;
      lowest_sum_ = std::min(lowest_sum_, sum);
      highest_sum_ = std::max(highest_sum_, sum);
    }
    std::stable_sort(influences.begin(), influences.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    if (influences.size() > deform::kInfluences) {
      ++report_.trimmed_influence_count;
      largest_dropped_ = std::max(largest_dropped_, influences[deform::kInfluences].second / sum);
      influences.resize(deform::kInfluences);
    }
    double kept = 0.0;
    for (const auto& influence : influences) kept += influence.second;
    for (std::size_t k = 0; k < influences.size(); ++k) {
      joints[k] = static_cast<std::uint16_t>(influences[k].first);
      weights[k] = static_cast<float>(influences[k].second / kept);
    }
  }
  glm::dmat4 skin(0.0);
  for (int k = 0; k < deform::kInfluences; ++k)
    if (weights[k] > 0.0f) skin += static_cast<double>(weights[k]) * skinning[joints[k]];
  model_.positions.push_back(glm::vec3(skin * glm::dvec4(position, 1.0)));
  glm::vec3 world_normal(0, 1, 0);
  if (normal) {
    const glm::dvec3 world = normal_matrix(skin) * *normal;
    const double length = glm::length(world);
    if (length > 0.0) world_normal = glm::vec3(world / length);
  } else {
    ++report_.computed_normal_count;
  }
  model_.normals.push_back(world_normal);
  has_normal_.push_back(normal != nullptr);
  if (!uv) ++missing_uvs_;
  model_.uvs.push_back(uv ? *uv : glm::vec2(0.0f));
  model_.skin_joints.push_back(joints);
  model_.skin_weights.push_back(weights);
}

void BindPoseVertices::finish(const deform::Skeleton& skeleton, const std::string& normal_name,
                              const std::string& uv_name) {
  if (missing_uvs_ == model_.uvs.size()) {
    model_.uvs.clear();
  } else if (missing_uvs_ > 0) {
    report_.warnings.push_back(std::to_string(missing_uvs_) + " vertices had no " + uv_name +
                               "; set to (0, 0)");
  }
  if (report_.computed_normal_count > 0) {
    const std::vector<glm::vec3> computed =
        deform::compute_vertex_normals(model_.positions, model_.indices);
    for (std::size_t v = 0; v < computed.size(); ++v)
      if (!has_normal_[v]) model_.normals[v] = computed[v];
    report_.warnings.push_back(std::to_string(report_.computed_normal_count) + " vertices had no " +
                               normal_name + "; computed from the triangles");
  }
  if (report_.renormalised_weight_count > 0)
    report_.warnings.push_back(std::to_string(report_.renormalised_weight_count) +
                               " vertices had skin weights not summing to 1 (lowest sum " +
                               std::to_string(lowest_sum_) + ", highest " +
                               std::to_string(highest_sum_) + "); renormalised");
  if (report_.trimmed_influence_count > 0)
    report_.warnings.push_back(std::to_string(report_.trimmed_influence_count) +
                               " vertices had more than 4 influences; kept the 4 largest "
                               "(the largest weight dropped: " +
                               std::to_string(largest_dropped_) + ")");
  if (report_.zero_weight_vertex_count > 0)
    report_.warnings.push_back(std::to_string(report_.zero_weight_vertex_count) +
                               " vertices had no skin weight; bound to joint '" +
                               skeleton.joints[fallback_used_].name + "'");
}

}  // namespace sweepd::io
