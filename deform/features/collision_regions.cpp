#include "deform/features/collision_regions.h"

#include <algorithm>
#include <map>

#include "deform/binding/rest_sweep.h"

namespace sweepd::deform {

const char* to_string(CollisionSite site) {
  switch (site) {
    case CollisionSite::kLeftElbow:
      return "left elbow";
    case CollisionSite::kRightElbow:
      return "right elbow";
    case CollisionSite::kLeftKnee:
      return "left knee";
    case CollisionSite::kRightKnee:
      return "right knee";
    case CollisionSite::kLeftShoulder:
      return "left shoulder";
    case CollisionSite::kRightShoulder:
      return "right shoulder";
    case CollisionSite::kLeftHip:
      return "left hip";
    case CollisionSite::kRightHip:
      return "right hip";
  }
  return "unknown";
}

bool is_elbow_or_knee(CollisionSite site) {
  return site == CollisionSite::kLeftElbow || site == CollisionSite::kRightElbow ||
         site == CollisionSite::kLeftKnee || site == CollisionSite::kRightKnee;
}

namespace {

int sweep_of(const BoundModel& bound, BodyPart part) {
  for (std::size_t s = 0; s < bound.sweeps.size(); ++s) {
    if (bound.sweeps[s].part == part) return static_cast<int>(s);
  }
  return -1;
}

// The sweep parameter of the joint key at `joint`, or -1 when the sweep has none.
double joint_key_parameter(const BoundSweep& sweep, const Sweep& curve, int joint) {
  for (std::size_t k = 0; k < sweep.anchors.size(); ++k) {
    if (sweep.anchors[k].joint == joint && sweep.anchors[k].is_joint_key())
      return curve.parameters()[k];
  }
  return -1.0;
}

double chord_length(const BoundSweep& sweep) {
  double length = 0.0;
  for (std::size_t k = 1; k < sweep.rest_keys.size(); ++k)
    length += glm::distance(sweep.rest_keys[k].centre, sweep.rest_keys[k - 1].centre);
  return length;
}

struct Limb {
  BodyPart part;
  int upper, lower, end;  // the limb's role joints: shoulder/hip, elbow/knee, wrist/ankle
};

struct Site {
  CollisionSite site;  // CollisionSite lists bends then roots in the order of `limbs` below
  Limb limb;
};

}  // namespace

CollisionRegions find_collision_regions(const BoundModel& bound,
                                        const CollisionRegionOptions& options) {
  const Model& model = bound.model;
  CollisionRegions out;
  out.representative.resize(model.vertex_count());
  {
    std::map<std::array<float, 3>, std::uint32_t> first_at;
    for (std::uint32_t v = 0; v < model.vertex_count(); ++v) {
      const glm::vec3& p = model.positions[v];
      // +0 and -0 are one position.
      const std::array<float, 3> key = {p.x + 0.0f, p.y + 0.0f, p.z + 0.0f};
      const auto [it, inserted] = first_at.emplace(key, v);
      out.representative[v] = it->second;
      if (!inserted) out.seam_copies.emplace_back(v, it->second);
    }
  }
  out.welded_indices.resize(model.indices.size());
  for (std::size_t i = 0; i < model.indices.size(); ++i)
    out.welded_indices[i] = out.representative[model.indices[i]];

  const RigMap& rig = bound.rig;
  const std::vector<glm::mat4> world_rest = model.skeleton.world_rest_matrices();
  auto joint_distance = [&](int a, int b) {
    return static_cast<double>(
        glm::distance(glm::vec3(world_rest[a][3]), glm::vec3(world_rest[b][3])));
  };
  // Elbows and knees first (the bends), then shoulders and hips (the roots).
  const Limb limbs[] = {
      {BodyPart::kLeftArm, rig.left_arm.upper, rig.left_arm.lower, rig.left_arm.hand},
      {BodyPart::kRightArm, rig.right_arm.upper, rig.right_arm.lower, rig.right_arm.hand},
      {BodyPart::kLeftLeg, rig.left_leg.upper, rig.left_leg.lower, rig.left_leg.foot},
      {BodyPart::kRightLeg, rig.right_leg.upper, rig.right_leg.lower, rig.right_leg.foot},
  };
  std::vector<Site> sites;
  for (int root = 0; root < 2; ++root) {
    for (int l = 0; l < 4; ++l)
      sites.push_back({static_cast<CollisionSite>(4 * root + l), limbs[l]});
  }
  const int torso = sweep_of(bound, BodyPart::kTorso);

  std::vector<std::uint8_t> inside(model.vertex_count());
  for (const Site& site : sites) {
    const Limb& joints = site.limb;
    const int limb = sweep_of(bound, joints.part);
    if (limb < 0 || joints.upper < 0 || joints.lower < 0 || joints.end < 0) continue;
    const BoundSweep& sweep = bound.sweeps[limb];
    const Sweep curve = rest_sweep(sweep, bound.options);
    const bool at_bend = is_elbow_or_knee(site.site);
    const double key_t = joint_key_parameter(sweep, curve, at_bend ? joints.lower : joints.upper);
    if (key_t < 0.0) continue;
    const double link = std::min(joint_distance(joints.upper, joints.lower),
                                 joint_distance(joints.lower, joints.end));
    const double window = options.joint_window * link / std::max(chord_length(sweep), 1e-9);

    std::fill(inside.begin(), inside.end(), 0);
    CollisionRegion region;
    region.site = site.site;
    region.joint = at_bend ? joints.lower : joints.upper;
    region.sweep = limb;
    for (std::uint32_t v = 0; v < model.vertex_count(); ++v) {
      const VertexBinding& binding = bound.vertices[v];
      bool on_limb = false, on_torso = false, near_key = false, past_key = false;
      float limb_weight = 0.0f, torso_weight = 0.0f;
      for (int k = 0; k < 2; ++k) {
        if (binding.sweep[k] < 0 || binding.weight[k] <= 0.0f) continue;
        if (binding.sweep[k] == limb) {
          on_limb = true;
          near_key |= std::abs(binding.coordinate[k].t - key_t) <= window;
          past_key = binding.coordinate[k].t > key_t;
          limb_weight = binding.weight[k];
        }
        if (binding.sweep[k] == torso) on_torso = true, torso_weight = binding.weight[k];
      }
      if (!near_key && !(!at_bend && on_limb && on_torso)) continue;
      // 1: before the joint, 2: past it.
      const bool past = at_bend ? past_key : (past_key && limb_weight >= torso_weight);
      inside[out.representative[v]] = past ? 2 : 1;
    }
    for (std::uint32_t v = 0; v < model.vertex_count(); ++v) {
      if (!inside[v]) continue;
      region.vertices.push_back(v);
      region.sides.push_back(inside[v] == 2 ? 1 : -1);
    }
    for (std::uint32_t t = 0; t < model.triangle_count(); ++t) {
      const std::uint32_t* corner = &out.welded_indices[3 * t];
      if (inside[corner[0]] || inside[corner[1]] || inside[corner[2]])
        region.triangles.push_back(t);
    }
    measure_rest_edges(region, model.positions, out.welded_indices);
    if (!region.triangles.empty()) out.regions.push_back(std::move(region));
  }
  return out;
}

void measure_rest_edges(CollisionRegion& region, std::span<const glm::vec3> rest,
                        std::span<const std::uint32_t> welded_indices) {
  region.rest_edges.clear();
  region.corner_slots.clear();
  for (std::uint32_t t : region.triangles) {
    const std::uint32_t* corner = &welded_indices[3 * t];
    for (int k = 0; k < 3; ++k) {
      region.rest_edges.push_back(glm::distance(rest[corner[k]], rest[corner[(k + 1) % 3]]));
      const auto at = std::lower_bound(region.vertices.begin(), region.vertices.end(), corner[k]);
      region.corner_slots.push_back(at != region.vertices.end() && *at == corner[k]
                                        ? static_cast<std::int32_t>(at - region.vertices.begin())
                                        : -1);
    }
  }
}

void copy_to_seam_copies(const CollisionRegions& regions, std::span<glm::vec3> positions) {
  for (const auto& [copy, representative] : regions.seam_copies)
    positions[copy] = positions[representative];
}

}  // namespace sweepd::deform
