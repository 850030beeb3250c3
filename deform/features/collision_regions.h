// Collision regions: the skin around elbows, knees, shoulders and hips where a bending limb can
// run into itself (paper §4.3) — the triangles that self-intersection detection, skin folding
// and bone protrusion look at. Built once per BoundModel; fixed afterwards.
//
// find_collision_regions
//   Inputs:  bound    a BoundModel (deform/binding/bind.h)
//            options  window sizes (below)
//   Output:  CollisionRegions:
//            representative  #V  per model vertex, the lowest-index vertex at exactly the same
//                                rest position (UV-seam copies share one; others map to
//                                themselves)
//            welded_indices  #I  the model's indices with every corner replaced by its
//                                representative: triangles across a UV seam share vertices
//            regions             up to 8 (elbows, knees, shoulders, hips, those the rig has):
//              vertices   representatives in the region, ascending
//              sides      per vertex, which side of the joint it lies on: -1 before it
//                         (upper arm, thigh, torso), +1 past it (forearm, shin, limb) — what
//                         skin folding uses to tell which skin went through which
//              triangles  ids of the mesh triangles with at least one corner in the region,
//                         ascending
// Elbow/knee: vertices bound to that limb's sweep with t within `joint_window` × the shorter
// adjacent link's length (in the sweep's chord-length parameter) of the joint's key.
// Shoulder/hip: vertices blended between the torso and that limb's sweep, plus limb vertices
// within the same window of the limb's first key.
//
// copy_to_seam_copies writes each representative's position to its UV-seam copies (after
// folding or protrusion moved representatives).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"

namespace sweepd::deform {

enum class CollisionSite {
  kLeftElbow,
  kRightElbow,
  kLeftKnee,
  kRightKnee,
  kLeftShoulder,
  kRightShoulder,
  kLeftHip,
  kRightHip,
};
const char* to_string(CollisionSite site);
bool is_elbow_or_knee(CollisionSite site);

struct CollisionRegion {
  CollisionSite site = CollisionSite::kLeftElbow;
  int joint = -1;  // the joint the region surrounds (elbow, knee, shoulder or hip)
  int sweep = -1;  // the limb sweep (index into BoundModel::sweeps)
  std::vector<std::uint32_t> vertices;
  std::vector<std::int8_t> sides;
  std::vector<std::uint32_t> triangles;
  // Per triangle of `triangles`, 3 each: its edges' rest lengths (corner k to corner k + 1,
  // welded), and its corners' indices into `vertices` (-1 for a corner outside the region).
  std::vector<float> rest_edges;
  std::vector<std::int32_t> corner_slots;
};

struct CollisionRegions {
  std::vector<std::uint32_t> representative;
  std::vector<std::uint32_t> welded_indices;
  std::vector<CollisionRegion> regions;
  // Pairs (copy, representative) for every vertex whose representative is another vertex.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> seam_copies;
};

struct CollisionRegionOptions {
  float joint_window = 0.7f;  // half-width, as a fraction of the shorter adjacent link
};

CollisionRegions find_collision_regions(const BoundModel& bound,
                                        const CollisionRegionOptions& options = {});

void copy_to_seam_copies(const CollisionRegions& regions, std::span<glm::vec3> positions);

// Fills region.rest_edges and region.corner_slots from the rest positions and the welded
// indices region.triangles index (region.vertices ascending).
void measure_rest_edges(CollisionRegion& region, std::span<const glm::vec3> rest,
                        std::span<const std::uint32_t> welded_indices);

}  // namespace sweepd::deform
