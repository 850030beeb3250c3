#include "metrics/crease_metrics.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <numbers>
#include <unordered_map>

#include "deform/binding/rest_sweep.h"
#include "deform/mesh/mesh_topology.h"
#include "deform/posing/sweep_poser_tables.h"

namespace sweepd::metrics {

using namespace deform;  // the metrics measure the deform library's types
namespace {

constexpr int kKinkAngles = 16;  // points of each key's ellipse where the kink is measured

double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

// The signed angle between the normals of triangles (a, b, left) and (b, a, right), about the
// edge a → b: 0 where they are coplanar.
float dihedral(std::span<const glm::vec3> p, std::uint32_t a, std::uint32_t b, std::uint32_t left,
               std::uint32_t right) {
  const glm::vec3 edge = p[b] - p[a];
  const glm::vec3 n1 = glm::cross(edge, p[left] - p[a]);
  const glm::vec3 n2 = glm::cross(p[a] - p[b], p[right] - p[b]);
  return std::atan2(glm::dot(glm::cross(n1, n2), glm::normalize(edge)), glm::dot(n1, n2));
}

// S(θ, t) from the sweep's double-precision curves.
glm::dvec3 sweep_point(const Sweep& sweep, double theta, double t) {
  const glm::dvec3 in_plane(
      sweep.offset_x_function().value(t) + sweep.a_function().value(t) * std::cos(theta),
      sweep.offset_y_function().value(t) + sweep.b_function().value(t) * std::sin(theta), 0.0);
  return sweep.centre_curve().position(t) + sweep.orientation_curve().rotation(t) * in_plane;
}

// The sweep whose weight is largest at v, or -1 where its skinned share is larger.
int region_of(const VertexBinding& vb) {
  int best = -1;
  float weight = vb.skin_weight;
  for (int k = 0; k < kSweepsPerVertex; ++k)
    if (vb.sweep[k] >= 0 && vb.weight[k] > weight) best = vb.sweep[k], weight = vb.weight[k];
  return best;
}

}  // namespace

double CreaseMetrics::largest_dihedral_change() const {
  double worst = 0.0;
  for (const RegionCrease& r : regions) worst = std::max(worst, r.dihedral_change);
  return worst;
}

double CreaseMetrics::largest_dihedral_change_at_keys() const {
  double worst = 0.0;
  for (const RegionCrease& r : regions) worst = std::max(worst, r.dihedral_change_at_keys);
  return worst;
}

double CreaseMetrics::largest_kink() const {
  double worst = 0.0;
  for (const RegionCrease& r : regions) worst = std::max(worst, r.kink);
  return worst;
}

double sweep_kink(const Sweep& sweep) {
  const auto t = sweep.parameters();
  double worst = 0.0;
  for (std::size_t i = 1; i + 1 < t.size(); ++i) {
    // One-sided differences 1e-4 of the neighbouring spans long: their O(h) error turns the
    // tangents by well under 0.05°.
    const double h = 1e-4 * (t[i + 1] - t[i - 1]);
    for (int k = 0; k < kKinkAngles; ++k) {
      const double theta = 2.0 * std::numbers::pi * k / kKinkAngles;
      const glm::dvec3 at = sweep_point(sweep, theta, t[i]);
      const glm::dvec3 before = at - sweep_point(sweep, theta, t[i] - h);
      const glm::dvec3 after = sweep_point(sweep, theta, t[i] + h) - at;
      worst = std::max(worst,
                       std::atan2(glm::length(glm::cross(before, after)), glm::dot(before, after)));
    }
  }
  return degrees(worst);
}

CreaseMeter::CreaseMeter(const BoundModel& bound) : bound_(bound) {
  const Model& model = bound.model;
  std::size_t welded_count = 0;
  const std::vector<std::uint32_t> welded =
      weld_coincident_positions(model.positions, &welded_count);
  std::vector<std::vector<double>> inner_keys;  // per sweep: t_1 .. t_{n-1}
  for (const BoundSweep& sweep : bound.sweeps) {
    const Sweep rest = rest_sweep(sweep, bound.options);
    inner_keys.emplace_back(rest.parameters().begin() + 1, rest.parameters().end() - 1);
  }
  // The first triangle met on each welded edge waits here for the second.
  std::unordered_map<std::uint64_t, Wing> open;
  for (std::size_t tri = 0; tri + 2 < model.indices.size(); tri += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = model.indices[tri + k], b = model.indices[tri + (k + 1) % 3];
      const std::uint32_t far = model.indices[tri + (k + 2) % 3];
      const std::uint64_t wa = welded[a], wb = welded[b];
      const std::uint64_t key = std::min(wa, wb) << 32 | std::max(wa, wb);
      const auto found = open.find(key);
      if (found == open.end()) {
        open.emplace(key, Wing{a, b, far, far, -1, false});
        continue;
      }
      Wing wing = found->second;
      open.erase(found);
      wing.right = far;
      const int region = region_of(bound.vertices[wing.a]);
      wing.region = static_cast<std::int16_t>(region);
      rest_dihedral_.push_back(dihedral(model.positions, wing.a, wing.b, wing.left, wing.right));
      wings_.push_back(wing);
      if (region < 0) continue;  // skinned: no region, measured only near a point
      double lo = 2.0, hi = -1.0;
      for (std::uint32_t v : {wing.a, wing.b, wing.left, wing.right})
        for (int s = 0; s < kSweepsPerVertex; ++s)
          if (bound.vertices[v].sweep[s] == region) {
            lo = std::min<double>(lo, bound.vertices[v].coordinate[s].t);
            hi = std::max<double>(hi, bound.vertices[v].coordinate[s].t);
          }
      for (double t : inner_keys[region])
        wings_.back().at_key = wings_.back().at_key || (lo <= t && t <= hi);
    }
}

CreaseMetrics CreaseMeter::measure(std::span<const glm::vec3> positions,
                                   const SweepPoser* posed) const {
  CreaseMetrics metrics;
  for (std::size_t s = 0; s < bound_.sweeps.size(); ++s) {
    metrics.regions.push_back({.part = bound_.sweeps[s].part});
    if (posed) metrics.regions.back().kink = sweep_kink(posed->sweep(static_cast<int>(s)));
  }
  for (std::size_t e = 0; e < wings_.size(); ++e) {
    const Wing& w = wings_[e];
    if (w.region < 0) continue;
    const double change = change_from_rest(positions, e);
    RegionCrease& region = metrics.regions[w.region];
    region.dihedral_change = std::max(region.dihedral_change, change);
    if (w.at_key) region.dihedral_change_at_keys = std::max(region.dihedral_change_at_keys, change);
  }
  return metrics;
}

double CreaseMeter::change_from_rest(std::span<const glm::vec3> positions, std::size_t e) const {
  const Wing& w = wings_[e];
  const double change =
      std::abs(dihedral(positions, w.a, w.b, w.left, w.right) - rest_dihedral_[e]);
  return degrees(std::min(change, 2.0 * std::numbers::pi - change));
}

double CreaseMeter::largest_dihedral_change_near(std::span<const glm::vec3> positions,
                                                 glm::vec3 centre, float radius) const {
  const std::vector<glm::vec3>& rest = bound_.model.positions;
  double worst = 0.0;
  for (std::size_t e = 0; e < wings_.size(); ++e) {
    const Wing& w = wings_[e];
    if (glm::distance(rest[w.a], centre) > radius || glm::distance(rest[w.b], centre) > radius)
      continue;
    worst = std::max(worst, change_from_rest(positions, e));
  }
  return worst;
}

Pose forearm_twist_pose(const BoundModel& bound, float degrees) {
  const Skeleton& skeleton = bound.model.skeleton;
  Pose pose = rest_pose(skeleton);
  const std::vector<glm::mat4> world = skeleton.world_rest_matrices();
  for (const ArmJoints* arm : {&bound.rig.left_arm, &bound.rig.right_arm}) {
    if (arm->lower < 0 || arm->hand < 0) continue;
    const glm::vec3 axis = glm::vec3(world[arm->hand][3]) - glm::vec3(world[arm->lower][3]);
    if (!(glm::length(axis) > 0.0f)) continue;
    // The hand's world rotation turned about the forearm axis, its parent at rest:
    // local' = parent⁻¹ · turn · parent · local.
    const int parent = skeleton.joints[arm->hand].parent;
    const glm::quat parent_rotation =
        parent >= 0 ? unit_rotation_of(world[parent]) : glm::quat(1, 0, 0, 0);
    const glm::quat turn = glm::angleAxis(glm::radians(degrees), glm::normalize(axis));
    pose.local_rotations[arm->hand] = glm::normalize(
        glm::inverse(parent_rotation) * turn * parent_rotation * pose.local_rotations[arm->hand]);
  }
  return pose;
}

}  // namespace sweepd::metrics
