#include "motion/body_floor.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deform/model/forward_kinematics.h"

namespace sweepd::motion {

namespace {

constexpr int kDirections = 64;

// kDirections unit vectors spread evenly over the sphere (a Fibonacci lattice).
std::vector<glm::vec3> sphere_directions() {
  std::vector<glm::vec3> directions;
  const float golden = static_cast<float>(M_PI) * (3.0f - std::sqrt(5.0f));
  for (int i = 0; i < kDirections; ++i) {
    const float y = 1.0f - 2.0f * (static_cast<float>(i) + 0.5f) / kDirections;
    const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
    directions.emplace_back(r * std::cos(golden * i), y, r * std::sin(golden * i));
  }
  return directions;
}

// Each vertex's strongest influence.
std::vector<int> strongest_joints(const deform::Model& model) {
  std::vector<int> strongest(model.vertex_count());
  for (std::size_t v = 0; v < model.vertex_count(); ++v) strongest[v] = model.strongest_joint(v);
  return strongest;
}

// The vertices furthest along each direction, per strongest joint, without repeats.
std::vector<std::uint32_t> extreme_vertices(const deform::Model& model,
                                            const std::vector<int>& strongest) {
  const int joints = model.skeleton.size();
  const std::vector<glm::vec3> directions = sphere_directions();
  std::vector<std::uint32_t> best(static_cast<std::size_t>(joints) * kDirections,
                                  std::numeric_limits<std::uint32_t>::max());
  std::vector<float> reach(best.size(), -std::numeric_limits<float>::infinity());
  for (std::uint32_t v = 0; v < model.vertex_count(); ++v)
    for (int d = 0; d < kDirections; ++d) {
      const std::size_t slot = static_cast<std::size_t>(strongest[v]) * kDirections + d;
      const float along = glm::dot(model.positions[v], directions[d]);
      if (along > reach[slot]) reach[slot] = along, best[slot] = v;
    }
  best.erase(std::remove(best.begin(), best.end(), std::numeric_limits<std::uint32_t>::max()),
             best.end());
  std::sort(best.begin(), best.end());
  best.erase(std::unique(best.begin(), best.end()), best.end());
  return best;
}

}  // namespace

BodyFloor BodyFloor::build(const deform::Model& model, const std::vector<bool>& feet, float floor,
                           int frame_count, double frame_time,
                           const std::function<deform::Pose(int)>& frame_pose) {
  BodyFloor body;
  body.frame_time_ = frame_time;
  body.lift_.assign(std::max(frame_count, 1), 0.0f);
  const std::vector<int> strongest = strongest_joints(model);
  const std::vector<std::uint32_t> samples = extreme_vertices(model, strongest);
  std::vector<float> lowest_allowed;
  for (std::uint32_t v : samples)
    lowest_allowed.push_back(feet.at(strongest[v]) ? floor - kSoleTolerance : floor + kClearance);
  if (samples.empty() || frame_count < 1) return body;
  const std::vector<glm::mat4> rest_inverse = deform::world_rest_inverse_matrices(model.skeleton);
  std::vector<glm::mat4> world(model.skeleton.size());
  std::vector<float> need(frame_count, 0.0f);
  for (int f = 0; f < frame_count; ++f) {
    deform::forward_kinematics(model.skeleton, frame_pose(f), world);
    float deepest = 0.0f;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const std::uint32_t v = samples[i];
      const glm::vec4 rest(model.positions[v], 1.0f);
      float y = 0.0f;
      for (int k = 0; k < deform::kInfluences; ++k) {
        const float w = model.skin_weights[v][k];
        if (w == 0.0f) continue;
        const int j = model.skin_joints[v][k];
        y += w * (world[j] * (rest_inverse[j] * rest)).y;
      }
      deepest = std::max(deepest, lowest_allowed[i] - y);
    }
    need[f] = deepest;
  }
  // Each need spreads kEase either side, falling linearly: the lift is their upper envelope.
  const int reach = std::max(1, static_cast<int>(std::ceil(kEase / frame_time)));
  for (int f = 0; f < frame_count; ++f) {
    if (need[f] <= 0.0f) continue;
    for (int g = std::max(0, f - reach); g <= std::min(frame_count - 1, f + reach); ++g) {
      const double gap = std::abs(g - f) * frame_time;
      const float share = static_cast<float>(std::max(0.0, 1.0 - gap / kEase));
      body.lift_[g] = std::max(body.lift_[g], need[f] * share);
    }
  }
  return body;
}

void BodyFloor::apply(double seconds, deform::Pose& pose) const {
  const int last = static_cast<int>(lift_.size()) - 1;
  const double position = std::clamp(seconds / frame_time_, 0.0, static_cast<double>(last));
  const int f0 = static_cast<int>(std::floor(position));
  const int f1 = std::min(f0 + 1, last);
  pose.root_translation.y += glm::mix(lift_[f0], lift_[f1], static_cast<float>(position - f0));
}

float BodyFloor::largest_lift() const {
  return lift_.empty() ? 0.0f : *std::max_element(lift_.begin(), lift_.end());
}

}  // namespace sweepd::motion
