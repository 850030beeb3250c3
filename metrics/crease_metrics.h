// Crease metrics of a deformed mesh against the rest pose — what shows as a fold line on the
// skin, per region (one per sweep, i.e. per body part):
// - the largest change of dihedral angle from rest across a welded edge (the signed angle
//   between the normals of the edge's two triangles, so a fold and an opening count alike),
//   over the region's edges and over those at a key (the edge's two triangles have vertices
//   bound to the region's sweep on both sides of an inner key's t_i: where the paper's
//   piecewise-linear Q(t) changes its turning rate);
// - the kink of the posed sweep at its inner keys: the largest angle between the surface's
//   one-sided tangents ∂S/∂t at t_i⁻ and t_i⁺ over the key's ellipse (zero for a C1 sweep; with
//   the centre curve and a, b C1 at keys it is the jump of N(t)'s turning there). Sweep
//   methods only.
// An edge belongs to the sweep that holds the largest weight at its first vertex, unless the
// vertex's skinned share is larger (hands, feet, head: no region).
// Inputs: the BoundModel; per measure: vertex_count() posed positions and, for the kink, the
// SweepPoser holding the deformation's own sweeps (null for LBS/DQS).
// Outputs: CreaseMetrics, angles in degrees; or the largest change near a point (a joint's ring).
// Not a per-frame hot path (allocates): ~10 ms for the shared male.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/model/pose.h"
#include "deform/posing/sweep_poser.h"

namespace sweepd::metrics {

struct RegionCrease {
  deform::BodyPart part = deform::BodyPart::kNone;
  double dihedral_change = 0.0;          // degrees, over the region's edges
  double dihedral_change_at_keys = 0.0;  // degrees, over its edges at an inner key
  double kink = 0.0;                     // degrees, the posed sweep's (0 without one)
};

struct CreaseMetrics {
  std::vector<RegionCrease> regions;  // one per sweep
  double largest_dihedral_change() const;
  double largest_dihedral_change_at_keys() const;
  double largest_kink() const;
};

// The largest angle (degrees) between ∂S/∂t on the two sides of the sweep's inner keys, over
// kKinkAngles points of each key's ellipse.
double sweep_kink(const deform::Sweep& sweep);

class CreaseMeter {
 public:
  explicit CreaseMeter(const deform::BoundModel& bound);
  // posed: the deformation's own sweeps (kink), or nullptr.
  CreaseMetrics measure(std::span<const glm::vec3> positions,
                        const deform::SweepPoser* posed) const;
  // The largest dihedral change from rest (degrees) over every welded edge, in a region or
  // skinned, whose both end vertices lie within `radius` of `centre` at rest: the crease of one
  // joint's ring (a shoulder, a hip), whichever sweep or skinning moves it.
  double largest_dihedral_change_near(std::span<const glm::vec3> positions, glm::vec3 centre,
                                      float radius) const;

  // The welded edges between two triangles one by one (metrics/region_quality.h sorts them into
  // body regions): its two end vertices (model ids), and the edge's dihedral change from rest,
  // degrees in [0, 180].
  std::size_t edge_count() const { return wings_.size(); }
  std::array<std::uint32_t, 2> edge_vertices(std::size_t e) const {
    return {wings_[e].a, wings_[e].b};
  }
  double change_from_rest(std::span<const glm::vec3> positions, std::size_t e) const;

 private:
  struct Wing {  // a welded edge (a, b) and the far vertices of its two triangles, model ids
    std::uint32_t a, b, left, right;
    std::int16_t region;  // sweep index, -1 for skinned
    bool at_key;
  };
  const deform::BoundModel& bound_;
  std::vector<Wing> wings_;
  std::vector<float> rest_dihedral_;  // radians, per wing
};

// A pose with both forearms twisted by `degrees` about their own axis (elbow → wrist) at the
// wrist: the candy-wrapper test of skinning. Joints the rig lacks are left at rest.
deform::Pose forearm_twist_pose(const deform::BoundModel& bound, float degrees);

}  // namespace sweepd::metrics
