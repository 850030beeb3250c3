// Region quality: how a posed mesh keeps its shape, body region by body region — what
// `sweepctl check` and the corpus gate compare between the sweep and skinning (issue 47).
//
// A vertex belongs to the body part (deform::label_joints) of its strongest skin joint; a joint
// above the pelvis counts as torso. An edge's length ratio and its crease count in the regions of
// both its vertices (edge_regions), a triangle in the region of each of its corners
// (triangle_regions): by every vertex, not the first, so that the order of an index buffer (a
// winding a mirrored copy reverses, corners a re-export rotates) moves nothing between regions.
// Per region and posed mesh:
//   stretch   the largest edge length ratio l / l_rest over its welded edges (1 at rest)
//   squash    the smallest l / l_rest (1 at rest)
//   crease    the largest change of dihedral angle from rest across its welded edges, degrees
//             (metrics/crease_metrics.h's, over every edge, not only the swept ones)
//   flipped   triangles whose normal points away (negative dot) from their rest normal turned
//             by each of their corners' strongest joints (flipped_from_rest): skin folded over
//             itself, which no rotation of a bone it hangs on explains (a triangle of zero rest
//             area has no rest normal and never counts)
// and the same over the swept part of the region alone (edges and triangles with a vertex that
// a sweep moves: VertexBinding::skin_weight < 1): where the sweep method differs from its own
// skinned remainder (LBS), so where comparing it with skinning judges the sweep.
// Inputs: positions (vertex_count()) and the posed joints' world matrices (the pose's forward
// kinematics). Not a per-frame hot path: ~10 ms for the shared male.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "metrics/crease_metrics.h"
#include "metrics/quality_metrics.h"

namespace sweepd::metrics {

struct RegionFigures {
  double stretch = 1.0, squash = 1.0, crease = 0.0;
  int flipped = 0;
  // Over the swept edges and triangles only.
  double swept_stretch = 1.0;
  int swept_flipped = 0;
  bool swept = false;  // whether the region has swept edges
};

// Issue 47's gate, one region in one frame: the sweep's figures against the better of LBS's and
// DQS's, over the region's swept edges and triangles (its skinned rest is the sweep method's LBS
// remainder, the same as LBS's own). Worse when the swept edges stretch more than
// kSkinningTolerance times the better baseline's, or more swept triangles flip than the better
// baseline flips. 2 % leaves room for the float noise of two deformations, not for a visible
// difference.
inline constexpr double kSkinningTolerance = 1.02;
struct SkinningComparison {
  bool swept = false;   // the region has swept edges (else there is nothing to judge)
  bool worse = false;
  double excess = 0.0;  // the sweep's ratio / (kSkinningTolerance x the baseline's)
  double sweep = 1.0, baseline = 1.0;  // the two ratios
};
SkinningComparison compare_with_skinning(const RegionFigures& sweep, const RegionFigures& lbs,
                                         const RegionFigures& dqs);

// The regions of a bound body: the body parts that hold a vertex, in deform::BodyPart order,
// and per vertex its region (index into regions) and its strongest skin joint.
struct RegionLabels {
  std::vector<deform::BodyPart> regions;
  std::vector<int> region_of_vertex;
  std::vector<int> strongest_joint;
};
RegionLabels label_regions(const deform::BoundModel& bound);
// The regions an edge is measured in: both its vertices' (the second -1 where they share one).
// By both, not by its first vertex, so that the edge's direction in the index buffer (a
// winding, which a mirrored copy reverses) does not move it from one region to the other.
std::array<int, 2> edge_regions(int region_a, int region_b);
// The regions a triangle is counted in: each of its corners' (-1 for a region already given),
// for the same reason, and so that rotating its corners (a re-export may) moves it nowhere.
std::array<int, 3> triangle_regions(int region_a, int region_b, int region_c);
// Whether a triangle whose posed normal is `normal` (unnormalised) flipped: it points away from
// rest_normal turned by each of its three corners' strongest joints (joint_turn: per joint, the
// pose's turn from rest, mat3(world x inverse rest)). By every corner, not the first, so that
// the corners' order does not decide it; where the turn of any bone the triangle hangs on
// explains its normal, it is not skin folded over itself.
// Per joint, the pose's turn from rest that flipped_from_rest takes: mat3(world x inverse rest).
std::vector<glm::mat3> joint_turns(std::span<const glm::mat4> joint_world,
                                   std::span<const glm::mat4> inverse_rest);
inline bool flipped_from_rest(glm::vec3 normal, glm::vec3 rest_normal,
                              std::span<const glm::mat3> joint_turn, const int* corner_joint) {
  for (int k = 0; k < 3; ++k)
    if (glm::dot(normal, joint_turn[corner_joint[k]] * rest_normal) >= 0.0f) return false;
  return true;
}

// Triangle t's normal, unnormalised (twice its area): (p1 - p0) x (p2 - p0).
inline glm::vec3 triangle_normal(std::span<const glm::vec3> p,
                                 std::span<const std::uint32_t> indices, std::size_t t) {
  const glm::vec3 a = p[indices[3 * t]], b = p[indices[3 * t + 1]], c = p[indices[3 * t + 2]];
  return glm::cross(b - a, c - a);
}

class RegionMeter {
 public:
  explicit RegionMeter(const deform::BoundModel& bound);
  // The regions the body has (those with at least one edge), in deform::BodyPart order.
  const std::vector<deform::BodyPart>& regions() const { return regions_; }
  // One RegionFigures per regions() entry.
  std::vector<RegionFigures> measure(std::span<const glm::vec3> positions,
                                     std::span<const glm::mat4> joint_world) const;

 private:
  int region_of_vertex(std::uint32_t v) const { return region_of_vertex_[v]; }

  const deform::BoundModel& bound_;
  QualityMeter quality_;
  CreaseMeter crease_;
  std::vector<deform::BodyPart> regions_;
  std::vector<int> region_of_vertex_;     // index into regions_
  std::vector<int> strongest_joint_;      // per vertex
  std::vector<bool> swept_;               // per vertex: skin_weight < 1
  std::vector<glm::mat4> inverse_rest_;   // per joint
  std::vector<glm::vec3> rest_normal_;    // per triangle (unnormalised)
};

}  // namespace sweepd::metrics
