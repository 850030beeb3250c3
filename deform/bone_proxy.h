// Bone proxies: the olecranon at each elbow and the patella at each knee, as small closed
// meshes that move rigidly with their bone, so the skin over them can be pushed out when a
// joint bends (paper §4.3, elbow and knee protrusion).
//
// make_bone_proxies
//   Inputs:  bound, regions (find_collision_regions: one proxy per elbow/knee region), options
//   Output:  one BoneProxy per elbow/knee: an ellipsoid (subdivided icosahedron, 42 vertices,
//            80 outward triangles) in world rest coordinates, attached to the forearm/shin joint.
//            Placed on the joint's key ellipse behind the elbow (−forward) or in front of the
//            knee (+forward), where forward = cross(left − right shoulder, up) as in binding;
//            its outermost point at `surface_fraction` × the key's extent in that direction;
//            half-axes radius_fraction × the key's smaller half-axis (1.5× that along the bone).
// pose_bone_proxy: positions (42) = skinning[proxy.joint] applied to the rest vertices; returns
//   the posed anchor (the key ellipse's centre, on the bone: where depth rays start).
// push_out_of_bone_proxy
//   Inputs:  the posed proxy (vertices, indices, anchor), its collision region, the welded
//            indices, gap (m)
//   In/out:  positions (#V): every region vertex inside the proxy moves along the ray from the
//            anchor through it to where the ray leaves the proxy, plus `gap` — outward, away
//            from the bone. Depth: the distance from the vertex to that exit point, found by
//            casting the ray against the proxy's triangles (inside: between the ray's first
//            and last hit).
//            Call copy_to_seam_copies afterwards.
//   Output:  ProtrusionResult (vertices moved, largest depth, volume change over the region).
// Only vertices are tested (as in the paper): a proxy smaller than the mesh spacing can poke
// through between vertices unnoticed. Measured on the shared male bent 150°: the default
// proxies (0.3 × the smaller half-axis, outermost point at 0.9 × the key's extent) stay under
// the skin, which the sweep keeps about one half-axis from the joint at any bend; proxies of
// 0.7 × at 1.0 × reach through at 2–11 vertices each and are pushed out (depth up to 32 mm).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/collision_regions.h"

namespace sweepd::deform {

struct BoneProxy {
  CollisionSite site = CollisionSite::kLeftElbow;
  int joint = -1;               // the bone it moves with (forearm or shin joint)
  int region = -1;              // index into CollisionRegions::regions
  glm::vec3 rest_anchor{0.0f};  // on the bone, at the joint's key centre
  glm::vec3 rest_centre{0.0f};  // the ellipsoid's centre
  std::vector<glm::vec3> rest_positions;
  std::vector<std::uint32_t> indices;
};

struct BoneProxyOptions {
  float radius_fraction = 0.3f;
  float surface_fraction = 0.9f;
};

struct ProtrusionResult {
  int moved = 0;
  float max_depth = 0.0f;      // m
  double volume_change = 0.0;  // enclosed volume after − before, over the region (m³)
};

std::vector<BoneProxy> make_bone_proxies(const BoundModel& bound, const CollisionRegions& regions,
                                         const BoneProxyOptions& options = {});

// Posed anchor of the proxy; writes rest_positions.size() posed vertices.
glm::vec3 pose_bone_proxy(const BoneProxy& proxy, std::span<const glm::mat4> skinning,
                          std::span<glm::vec3> positions);

// Depth of `point` inside the posed (convex) proxy, 0 outside, by casting the ray anchor →
// point against the proxy's triangles; *surface receives where the ray leaves the proxy.
float penetration_depth(std::span<const glm::vec3> proxy_positions,
                        std::span<const std::uint32_t> proxy_indices, glm::vec3 anchor,
                        glm::vec3 point, glm::vec3* surface = nullptr);

ProtrusionResult push_out_of_bone_proxy(std::span<const glm::vec3> proxy_positions,
                                        std::span<const std::uint32_t> proxy_indices,
                                        glm::vec3 anchor, const CollisionRegion& region,
                                        std::span<const std::uint32_t> indices, float gap,
                                        std::span<glm::vec3> positions);

}  // namespace sweepd::deform
