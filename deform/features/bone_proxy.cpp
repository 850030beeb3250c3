#include "deform/features/bone_proxy.h"

#include <algorithm>
#include <array>
#include <map>

#include "deform/mesh/enclosed_volume.h"

namespace sweepd::deform {
namespace {

// Unit icosphere, one subdivision: 42 vertices, 80 outward triangles.
void unit_icosphere(std::vector<glm::vec3>& positions, std::vector<std::uint32_t>& indices) {
  const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
  positions = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
               {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  for (glm::vec3& p : positions) p = glm::normalize(p);
  const std::vector<std::uint32_t> base = {0, 11, 5, 0, 5,  1,  0,  1,  7,  0,  7, 10, 0, 10, 11,
                                           1, 5,  9, 5, 11, 4,  11, 10, 2,  10, 7, 6,  7, 1,  8,
                                           3, 9,  4, 3, 4,  2,  3,  2,  6,  3,  6, 8,  3, 8,  9,
                                           4, 9,  5, 2, 4,  11, 6,  2,  10, 8,  6, 7,  9, 8,  1};
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
  auto middle = [&](std::uint32_t a, std::uint32_t b) {
    const auto key = std::minmax(a, b);
    const auto [it, inserted] = midpoint.emplace(key, static_cast<std::uint32_t>(positions.size()));
    if (inserted) positions.push_back(glm::normalize(positions[a] + positions[b]));
    return it->second;
  };
  indices.clear();
  for (std::size_t t = 0; t < base.size(); t += 3) {
    const std::uint32_t a = base[t], b = base[t + 1], c = base[t + 2];
    const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
    for (std::uint32_t k : {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca}) indices.push_back(k);
  }
}

const KeyEllipse* joint_key(const BoundSweep& sweep, int joint) {
  for (std::size_t k = 0; k < sweep.anchors.size(); ++k) {
    if (sweep.anchors[k].joint == joint && sweep.anchors[k].is_joint_key())
      return &sweep.rest_keys[k];
  }
  return nullptr;
}

// The joint the bent limb's upper segment starts at: shoulder for an elbow, hip for a knee.
int upper_joint(const RigMap& rig, CollisionSite site) {
  switch (site) {
    case CollisionSite::kLeftElbow:
      return rig.left_arm.upper;
    case CollisionSite::kRightElbow:
      return rig.right_arm.upper;
    case CollisionSite::kLeftKnee:
      return rig.left_leg.upper;
    default:
      return rig.right_leg.upper;
  }
}

constexpr float kMiss = -INFINITY;

// Möller–Trumbore: signed distance along the unit line to the triangle, kMiss when it misses.
float ray_hits_triangle(glm::vec3 origin, glm::vec3 direction, glm::vec3 a, glm::vec3 b,
                        glm::vec3 c) {
  const glm::vec3 e1 = b - a, e2 = c - a, h = glm::cross(direction, e2);
  const float det = glm::dot(e1, h);
  if (std::abs(det) < 1e-20f) return kMiss;
  const glm::vec3 s = origin - a;
  const float u = glm::dot(s, h) / det;
  if (u < 0.0f || u > 1.0f) return kMiss;
  const glm::vec3 q = glm::cross(s, e1);
  const float v = glm::dot(direction, q) / det;
  if (v < 0.0f || u + v > 1.0f) return kMiss;
  return glm::dot(e2, q) / det;
}

}  // namespace

std::vector<BoneProxy> make_bone_proxies(const BoundModel& bound, const CollisionRegions& regions,
                                         const BoneProxyOptions& options) {
  const RigMap& rig = bound.rig;
  const std::vector<glm::mat4> world_rest = bound.model.skeleton.world_rest_matrices();
  auto position = [&](int joint) { return glm::vec3(world_rest[joint][3]); };
  const glm::vec3 forward = rest_body_axes(rig, world_rest).forward;

  std::vector<glm::vec3> sphere;
  std::vector<std::uint32_t> sphere_indices;
  unit_icosphere(sphere, sphere_indices);

  std::vector<BoneProxy> proxies;
  for (std::size_t r = 0; r < regions.regions.size(); ++r) {
    const CollisionRegion& region = regions.regions[r];
    if (!is_elbow_or_knee(region.site)) continue;
    const KeyEllipse* key = joint_key(bound.sweeps[region.sweep], region.joint);
    if (key == nullptr) continue;
    const bool elbow =
        region.site == CollisionSite::kLeftElbow || region.site == CollisionSite::kRightElbow;
    const glm::mat3 frame = glm::mat3_cast(key->orientation);
    // The outward direction in the key's plane, and the key's extent along it.
    glm::vec3 out = elbow ? -forward : forward;
    out = glm::normalize(out - glm::dot(out, frame[2]) * frame[2]);
    const float dx = glm::dot(out, frame[0]), dy = glm::dot(out, frame[1]);
    const float key_extent = std::sqrt(key->a * dx * key->a * dx + key->b * dy * key->b * dy);
    // The rest skin's depth along `out`: the nearest region vertex within 30° of the ray and
    // within a quarter of the key's extent from its plane (the key can be wider than the skin).
    float extent = key_extent;
    for (std::uint32_t v : region.vertices) {
      const glm::vec3 d = bound.model.positions[v] - key->centre;
      const float along = glm::dot(d, out);
      if (std::abs(glm::dot(d, frame[2])) > 0.25f * key_extent || along <= 0.0f) continue;
      if (along < std::cos(glm::radians(30.0f)) * glm::length(d - glm::dot(d, frame[2]) * frame[2]))
        continue;
      extent = std::min(extent, along);
    }
    const float radius = options.radius_fraction * std::min(key->a, key->b);
    const glm::vec3 side = glm::cross(frame[2], out);
    BoneProxy proxy;
    proxy.site = region.site;
    proxy.joint = region.joint;
    proxy.region = static_cast<int>(r);
    proxy.rest_anchor = key->centre;
    glm::vec3 proximal = position(upper_joint(rig, region.site)) - position(region.joint);
    proximal = glm::normalize(proximal - glm::dot(proximal, out) * out);
    proxy.rest_centre = key->centre + out * (options.surface_fraction * extent - radius) +
                        proximal * (options.proximal_fraction * extent);
    for (const glm::vec3& s : sphere) {
      proxy.rest_positions.push_back(proxy.rest_centre + out * (s.x * radius) +
                                     side * (s.y * radius) + frame[2] * (s.z * 1.5f * radius));
    }
    proxy.indices = sphere_indices;
    // (out, side, N) is right-handed, so the unit sphere's outward winding is kept.
    proxies.push_back(std::move(proxy));
  }
  return proxies;
}

glm::vec3 pose_bone_proxy(const BoneProxy& proxy, std::span<const glm::mat4> skinning,
                          std::span<glm::vec3> positions) {
  const glm::mat4& m = skinning[proxy.joint];
  for (std::size_t i = 0; i < proxy.rest_positions.size(); ++i)
    positions[i] = glm::vec3(m * glm::vec4(proxy.rest_positions[i], 1.0f));
  return glm::vec3(m * glm::vec4(proxy.rest_anchor, 1.0f));
}

float penetration_depth(std::span<const glm::vec3> proxy_positions,
                        std::span<const std::uint32_t> proxy_indices, glm::vec3 anchor,
                        glm::vec3 point, glm::vec3* surface) {
  const glm::vec3 offset = point - anchor;
  const float distance = glm::length(offset);
  if (!(distance > 0.0f)) return 0.0f;
  const glm::vec3 direction = offset / distance;
  float entry = INFINITY, exit = -INFINITY;
  for (std::size_t t = 0; t + 2 < proxy_indices.size(); t += 3) {
    const float hit = ray_hits_triangle(anchor, direction, proxy_positions[proxy_indices[t]],
                                        proxy_positions[proxy_indices[t + 1]],
                                        proxy_positions[proxy_indices[t + 2]]);
    if (hit == kMiss) continue;
    entry = std::min(entry, hit);
    exit = std::max(exit, hit);
  }
  if (!(entry <= distance && distance < exit)) return 0.0f;
  if (surface != nullptr) *surface = anchor + direction * exit;
  return exit - distance;
}

ProtrusionResult push_out_of_bone_proxy(std::span<const glm::vec3> proxy_positions,
                                        std::span<const std::uint32_t> proxy_indices,
                                        glm::vec3 anchor, const CollisionRegion& region,
                                        std::span<const std::uint32_t> indices, float gap,
                                        std::span<glm::vec3> positions) {
  ProtrusionResult result;
  const double volume_before = enclosed_volume(positions, indices, region.triangles);
  // Only vertices within the proxy's bounding sphere can be inside it.
  glm::vec3 centre(0.0f);
  for (const glm::vec3& p : proxy_positions) centre += p;
  centre /= static_cast<float>(proxy_positions.size());
  float reach = 0.0f;
  for (const glm::vec3& p : proxy_positions) reach = std::max(reach, glm::distance(p, centre));
  for (std::uint32_t v : region.vertices) {
    if (glm::distance(positions[v], centre) > reach) continue;
    glm::vec3 surface;
    const float depth =
        penetration_depth(proxy_positions, proxy_indices, anchor, positions[v], &surface);
    if (depth <= 0.0f) continue;
    positions[v] = surface + glm::normalize(surface - anchor) * gap;
    result.max_depth = std::max(result.max_depth, depth);
    ++result.moved;
  }
  result.volume_change = enclosed_volume(positions, indices, region.triangles) - volume_before;
  return result;
}

}  // namespace sweepd::deform
