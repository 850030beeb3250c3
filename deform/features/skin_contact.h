// Whole-body skin contact (beyond the paper, which limits collision to elbows and knees and names
// whole-body features as future work): every pair of non-adjacent skin triangles that pass
// through each other anywhere on the body — forearm into thigh, upper arm into chest, thigh into
// thigh, hand into face — resolved with the paper's folding rule (§4.3): per connected group of
// intersecting triangles a least-squares bisecting plane, both skins pulled back behind it with
// a small gap (skin_folding.h's pull_back_to_plane). A group is first cut into pieces: one plane
// cannot fit a contact that curves along a limb (a forearm lying along a thigh, an arm pressed
// from chest to hip), so a group more than twice as long as wide in its plane is cut at the
// median of its longest axis, again and again, and each piece gets its own plane.
//
// make_contact_model(bound, welded_indices) — once per model:
//   skin_triangles  the triangles of the swept body (binding/mesh_parts_joined.h): the body's
//                   skinned parts. Rigid props and separate pieces (a visor, a prop in a hand)
//                   are left out: they follow one joint or LBS, are not skin, and pulling them
//                   back would bend a rigid thing; touching them is not the skin's contact.
//   rest_pairs      the skin's pairs that intersect already in the rest pose (the mesh's own
//                   intersections — a closed mouth, a fingertip in its neighbour, separate
//                   skinned pieces of the body overlapping): excluded from contact, so the rest
//                   pose has none and only what the pose did is resolved.
//   adjacency       vertex adjacency over the welded indices (the skin around a contact)
//   triangle_sweep  per mesh triangle, the sweep its first corner is bound to most (-1: none):
//                   where the triangle's volume change goes in I_C (paper §4.4)
// remove_rest_pairs(rest, pairs): pairs minus rest (both sorted), in place.
// skin_sweep_volumes(model, indices, positions, volumes): per sweep (volumes.size() values),
//   Σ dot(p, cross(q, r)) / 6 over its skin triangles — the difference of two calls is the volume
//   change per sweep (the skin is closed, so only moved triangles change it).
//
// ContactResolver::resolve
//   Inputs:  model, indices (the welded ones the pairs came from), pairs (contact pairs of the
//            posed skin, rest pairs removed), gap (m left between each skin and the plane)
//   In/out:  positions #V: skin representatives move (call copy_to_seam_copies afterwards)
//            only_group  >= 0: resolve that piece of the last full resolve only (same pairs;
//                        its pieces are kept, so a piece keeps its index after others moved
//                        the skin), else find the groups and pieces and resolve them all
//   Output:  ContactResult
// Sides (per piece, called a group below). A group (intersecting triangles joined through pairs and shared vertices) holds two
// skins, but not "before and after a joint" as a region does. Its triangles split into
// mesh-connected patches (through shared welded vertices only). Each patch's area-weighted
// normal points out of the body it belongs to, so that body lies behind it: the patch goes to
// the plane side its normal points away from (the two skins of a contact face each other).
// When that leaves one side empty (one skin crumpled into itself, or the two skins joined
// inside the group), each triangle is judged by its own normal instead; when still one-sided,
// the group is left alone. The moving skin: every vertex mesh-connected to a patch within
// reach of the plane (in-plane distance < 2 extents, distance to the plane < 1 extent + 4
// gaps: wider, the grown skin wraps round limbs and counts their far side as gone through), grown
// breadth-first from all patches at once, so each vertex follows the nearest patch. Then
// pull_back_to_plane as folding does. Buffers are kept between calls. moved_group(i), i <
// moved_groups(): the vertices the last resolve moved for its i-th separated group (a caller
// restores those of a group that made things worse).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/features/self_intersection.h"
#include "deform/features/skin_folding.h"
#include "deform/mesh/vertex_adjacency.h"

namespace sweepd::deform {

struct ContactModel {
  std::vector<std::uint32_t> skin_triangles;  // ascending
  std::vector<TrianglePair> rest_pairs;       // sorted
  VertexAdjacency adjacency;
  std::vector<std::int16_t> triangle_sweep;  // per mesh triangle
};

ContactModel make_contact_model(const BoundModel& bound,
                                std::span<const std::uint32_t> welded_indices);

void remove_rest_pairs(std::span<const TrianglePair> rest, std::vector<TrianglePair>& pairs);

void skin_sweep_volumes(const ContactModel& model, std::span<const std::uint32_t> indices,
                        std::span<const glm::vec3> positions, std::span<double> volumes);

struct ContactResult {
  int groups = 0;          // pieces of the connected groups of intersecting triangles
  int separated = 0;       // of them, those with skin on both sides of their plane
  int moved = 0;           // vertices that had gone through a plane and were pulled back
  float max_depth = 0.0f;  // largest penetration depth (m)
};

// Whether moving `moved` from `before` to `positions` (both #V) stretched an edge at one of
// them past kMostFoldStretch times its rest length and past its length before: a tear, which
// contact never keeps.
bool tears_around(const ContactModel& model, std::span<const std::uint32_t> moved,
                  std::span<const glm::vec3> before, std::span<const glm::vec3> positions);

class ContactResolver {
 public:
  ContactResult resolve(const ContactModel& model, std::span<const std::uint32_t> indices,
                        std::span<const TrianglePair> pairs, float gap,
                        std::span<glm::vec3> positions, int only_group = -1);
  std::size_t moved_groups() const { return moved_start_.size() - 1; }
  std::span<const std::uint32_t> moved_group(std::size_t i) const {
    return std::span(moved_).subspan(moved_start_[i], moved_start_[i + 1] - moved_start_[i]);
  }

 private:
  // Sides of the group's triangles into triangle_side_; false when only one side is found.
  bool find_sides(std::span<const std::uint32_t> triangles, std::span<const std::uint32_t> indices,
                  std::span<const glm::vec3> positions, const glm::vec3& normal);
  std::uint32_t find(std::uint32_t slot);
  // Appends a group's triangles to piece_triangles_ and its pieces' ends to piece_start_, cut
  // at the median along their longest in-plane axis until each piece is no more than
  // kMostElongation times as long as wide (spread's eigenvalues) or has fewer than
  // 2 kSmallestPiece triangles.
  void split_elongated(std::span<const std::uint32_t> triangles,
                       std::span<const std::uint32_t> indices,
                       std::span<const glm::vec3> positions);
  static constexpr float kMostElongation = 2.0f;
  static constexpr std::uint32_t kSmallestPiece = 8;
  std::vector<std::uint32_t> piece_triangles_, piece_start_{0};
  std::vector<std::pair<std::uint32_t, std::uint32_t>> split_todo_, split_done_;
  std::vector<glm::vec3> centres_;

  IntersectingGroups groups_;
  std::vector<glm::vec3> points_;
  std::vector<std::uint32_t> parent_;       // per group triangle: patch union-find
  std::vector<std::int32_t> owner_;         // per vertex: a group triangle using it, -1
  std::vector<glm::vec3> patch_normal_;     // per group triangle (at its patch root)
  std::vector<std::int8_t> triangle_side_;  // per group triangle
  std::vector<std::int8_t> label_;          // per vertex: 0, or the side it moves to
  std::vector<std::uint32_t> grown_;        // the moving skin, in breadth-first order
  std::vector<std::int8_t> grown_side_;
  std::vector<std::uint32_t> moved_, moved_start_{0};
};

}  // namespace sweepd::deform
