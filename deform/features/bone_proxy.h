// Bone proxies: the olecranon at each elbow and the patella at each knee, as small closed
// meshes that move rigidly with their bone, so the skin over them can be pushed out when a
// joint bends (paper §4.3, elbow and knee protrusion).
//
// make_bone_proxies
//   Inputs:  bound, regions (find_collision_regions: one proxy per elbow/knee region), options
//   Output:  one BoneProxy per elbow/knee: an ellipsoid (subdivided icosahedron, 42 vertices,
//            80 outward triangles) in world rest coordinates, attached to the forearm/shin joint.
//            Placed behind the elbow (−forward) or in front of the knee (+forward), where
//            forward = cross(left − right shoulder, up) as in binding: `out` is that direction
//            in the joint's key plane, depth the rest skin's distance from the key centre along
//            it (the nearest region vertex within 30° of the ray and near the key plane; the key
//            ellipse itself can reach well past the skin). Outermost point at
//            surface_fraction × depth along `out`, centre moved proximal_fraction × depth toward
//            the upper joint (shoulder/hip) — where the olecranon and the patella sit, so that
//            flexing carries them to the tip of the bend; half-axes radius_fraction × the key's
//            smaller half-axis (1.5× that along the bone).
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
// through between vertices unnoticed. Measured on the shared male
// (tests/deform/features/collision_features_test.cpp): at rest no skin vertex is inside any default
// proxy; with the left elbow and knee bent 150°, 10 skin vertices are inside the olecranon and
// 4 inside the patella before protrusion, 0 after (the unbent right side: 0).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/features/collision_regions.h"

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
  float radius_fraction = 0.5f;    // half-axes, × the key's smaller half-axis
  float surface_fraction = 0.9f;   // outermost point, × the rest skin's depth behind/in front
  float proximal_fraction = 0.3f;  // centre moved toward the upper limb, × that depth
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
