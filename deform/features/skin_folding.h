// Skin folding (paper §4.3): where a bending joint makes the skin pass through itself, a
// least-squares bisecting plane is fitted to the intersecting triangles' vertices, and the skin
// that went through the plane is pulled back behind it — the two skins meet along the plane
// and a fold forms.
//
// SkinFolder::fold
//   Inputs:  region     a collision region (deform/features/collision_regions.h): its vertices and
//   the
//                       side of the joint each lies on
//            indices    the welded indices the pairs were found with
//            pairs      intersecting triangle pairs of the region (SelfIntersectionDetector)
//            gap        distance (m) left between a pulled-back vertex and the plane, on its
//                       own side, so the two skins touch without crossing
//   In/out:  positions  #V; only region vertices move (call copy_to_seam_copies afterwards)
//            volume_change: over region.triangles (which hold every triangle of a moved vertex)
//   Output:  FoldingResult
// Groups: intersecting triangles connected through pairs or shared vertices. One plane per
// group (a plane across two separate groups tilts between them and can add pairs: cmu_01_03
// frame 2000 went 18 -> 59 with one plane per call), through the centroid of the group's
// distinct vertices, normal along their covariance's smallest eigenvector, oriented from the
// region's "before the joint" vertices to its "past the joint" ones. Penetration depth of a
// vertex: how far it lies past the plane on the other side's half-space. Every region vertex
// within one extent of the plane's centre (the group's largest in-plane distance; fading out
// smoothly to two extents) is pulled back along the normal: own-side distances in
// [-deepest, band] map linearly onto [gap, band], band = 2 deepest + 4 gap. So the skin that
// went through ends behind the plane and the layers keep their order (projected onto the plane
// itself they would lie coplanar and overlap).
//
// SkinFolder::relax: the other step CollisionFeatures tries between detections — 12 Jacobi
// iterations moving each region corner of the intersecting triangles half-way to the mean of
// its mesh neighbours: it unfolds small in-plane crumples that moving along a normal cannot.
// Buffers are kept between calls (no allocation once warm).
// No tears: a group's pull-back is kept only if it stretches no edge of the region past
// kMostFoldStretch times its rest length (unless the edge was stretched so far already); else
// a half, a quarter, an eighth of it, else none (FoldingResult::eased, refused). Without that
// check a hanging arm's armpit (the fold plane of skin that lies against the chest rather than
// bends across a joint, pulled back by up to 21 cm) and even the 150° elbow stretched edges
// 10-34 times their rest length.
// Measured on the shared male (tests/deform/features/collision_features_test.cpp), one fold call
// (pairs, and pairs of skin through skin: a triangle wholly before the joint and one wholly
// past it): elbow at 135° 77 -> 27 (52 -> 19), knee at 135° 57 -> 9 (48 -> 0), elbow at 150°
// 92 -> 78 (68 -> 58), knee at 150° 78 -> 79 (71 -> 68); the elbow's region stretched 2.84x and
// 3.38x by the sweep ends at 2.38x and 2.80x. With CollisionFeatures' rounds (fold, else relax,
// kept only when the pairs drop and nothing tears): the elbow and knee at 135° and 150° -> 0;
// at 160° elbow 97 -> 79, knee 97 -> 97.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/features/collision_regions.h"
#include "deform/features/self_intersection.h"

namespace sweepd::deform {

// A group's pull-back may stretch a region edge to this many times its rest length (or keep
// it as stretched as it was), no further; the bound on every edge is 3x.
inline constexpr float kMostFoldStretch = 2.5f;
// The smallest share of a pull-back tried before the group is left as it was.
inline constexpr float kSmallestShare = 0.125f;

struct FoldingResult {
  int groups = 0;              // connected groups of intersecting triangles
  int eased = 0;               // groups pulled back only part of the way (a tear otherwise)
  int refused = 0;             // groups left as they were (even an eighth tore the skin)
  int moved = 0;               // vertices that had gone through the plane and were pulled back
  float max_depth = 0.0f;      // largest penetration depth (m)
  double volume_change = 0.0;  // enclosed volume after − before, over the region (m³)
};

// Plane fitted by least squares to points: returns the unit normal (smallest-variance
// direction) and writes the centroid. Points must not be empty.
glm::vec3 fit_plane(std::span<const glm::vec3> points, glm::vec3& centroid);

// Connected groups of intersecting triangles: joined through pairs and through shared vertex
// indices (pass the welded indices the pairs were found with). build(): #V = vertex_count
// (scratch), then per group g < size(): triangles(g) and its distinct corners vertices(g), each
// once. Buffers are kept between calls.
class IntersectingGroups {
 public:
  void build(std::span<const std::uint32_t> indices, std::span<const TrianglePair> pairs,
             std::size_t vertex_count);
  std::size_t size() const { return group_start_.size() - 1; }
  std::span<const std::uint32_t> triangles(std::size_t g) const {
    return std::span(group_triangles_)
        .subspan(group_start_[g], group_start_[g + 1] - group_start_[g]);
  }
  std::span<const std::uint32_t> vertices(std::size_t g) const {
    return std::span(group_vertices_)
        .subspan(vertex_start_[g], vertex_start_[g + 1] - vertex_start_[g]);
  }

 private:
  std::uint32_t find(std::uint32_t slot);
  std::vector<std::uint32_t> triangles_, parent_;
  std::vector<std::int32_t> slot_of_vertex_;                    // per mesh vertex, -1 when unused
  std::vector<std::pair<std::uint32_t, std::uint32_t>> order_;  // (group root, slot)
  std::vector<std::uint32_t> group_start_{0}, group_triangles_, vertex_start_{0}, group_vertices_;
};

// The largest in-plane distance of points from centre (normal: unit).
float in_plane_extent(std::span<const glm::vec3> points, const glm::vec3& centre,
                      const glm::vec3& normal);

// The pull-back of fold(), for any skin split in two: vertices[i] belongs on side sides[i]
// (-1: behind the plane, against normal; +1: in front). Within reach of the centre (full
// within one `extent` in the plane, fading out by two) each side's vertices are mapped from
// [-deepest, band] onto [gap, band] of own-side distance, band = 2 deepest + 4 gap (see above).
// Counts into result: moved, max_depth.
void pull_back_to_plane(const glm::vec3& centre, const glm::vec3& normal, float extent,
                        std::span<const std::uint32_t> vertices, std::span<const std::int8_t> sides,
                        float gap, std::span<glm::vec3> positions, FoldingResult& result);

// Whether moving the region's vertices from `before` (one per region vertex, in its order) to
// `positions` stretched an edge of its triangles past kMostFoldStretch times its rest length
// and past its length before: a tear, which folding never keeps.
bool tears_skin(const CollisionRegion& region, std::span<const std::uint32_t> indices,
                std::span<const glm::vec3> before, std::span<const glm::vec3> positions);

class SkinFolder {
 public:
  FoldingResult fold(const CollisionRegion& region, std::span<const std::uint32_t> indices,
                     std::span<const TrianglePair> pairs, float gap,
                     std::span<glm::vec3> positions);
  // Smooths the region corners of the pairs' triangles toward their neighbours (see above).
  void relax(const CollisionRegion& region, std::span<const std::uint32_t> indices,
             std::span<const TrianglePair> pairs, std::span<glm::vec3> positions);

 private:
  void pull_back(const CollisionRegion& region, float gap, std::span<glm::vec3> positions,
                 FoldingResult& result);

  IntersectingGroups groups_;
  std::vector<glm::vec3> points_, before_, after_;
  std::vector<std::uint8_t> mark_;
  std::vector<glm::vec3> sum_;
  std::vector<int> count_;
};

}  // namespace sweepd::deform
