// Quality metrics of a deformed mesh against the rest pose — the figures that compare sweep
// deformation (with and without volume preservation) to LBS and DQS:
// - per body part (one per sweep), the volume change against rest of
//   · the closed part region (deform/volume/part_volume_regions.h): the triangles bound to the
//   part's sweep
//     with a mean weight >= 0.5, every boundary loop capped by a fan to its centroid, signed
//     volume by the divergence theorem (double precision);
//   · the sweep integral I of the posed sweep (sweep methods only);
// - the smallest limb cross-section area ratio: the mesh cut by the planes (C(t), N(t)) of the
//   posed limb sweeps at kSectionsPerLimb parameters, loop area over the rest area there;
// - self-intersecting triangle pairs (triangles sharing no welded vertex; a uniform grid of
//   triangle bounds, bound overlap, plane sides, then edge–triangle crossings; coplanar
//   touching is not counted);
// - the shortest and the longest welded edge as length ratios l / l_rest;
// - the rest-pose error: the largest distance to the rest positions (measure it on the rest
//   pose's output).
// Inputs: positions: vertex_count() posed positions; the SweepPoser posed to the same pose
// (its sweeps give the section planes and I). Outputs: QualityMetrics.
// Not a per-frame hot path (each call allocates scratch): 30-45 ms for the shared male.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <utility>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/posing/sweep_poser.h"
#include "deform/volume/part_volume_regions.h"

namespace sweepd::metrics {

struct PartMetrics {
  deform::BodyPart part = deform::BodyPart::kNone;
  double mesh_volume_change = 0.0;   // (V − V_rest) / V_rest of the closed part region
  double sweep_volume_change = 0.0;  // (I − I_0) / I_0; 0 where not measured
};

struct QualityMetrics {
  std::vector<PartMetrics> parts;                              // one per sweep
  double smallest_section_ratio = 1.0;                         // over the arm and leg sweeps
  int self_intersections = 0;                                  // triangle pairs
  double shortest_edge_ratio = 1.0, longest_edge_ratio = 1.0;  // edges as l / l_rest
};

// Triangle pairs that cross each other; triangles sharing a (welded) vertex are skipped.
// welded: per-vertex welded ids (weld_coincident_positions), indices: 3 per triangle.
int count_self_intersections(std::span<const glm::vec3> positions,
                             std::span<const std::uint32_t> indices,
                             std::span<const std::uint32_t> welded);

// Largest distance between two position sets of the same size.
double largest_distance(std::span<const glm::vec3> a, std::span<const glm::vec3> b);

// Each welded edge once, as the two model vertices of its first occurrence (2 per edge), in the
// order the triangles first name them. welded: per-vertex welded ids.
std::vector<std::uint32_t> welded_edges(std::span<const std::uint32_t> indices,
                                        std::span<const std::uint32_t> welded);

class QualityMeter {
 public:
  static constexpr int kSectionsPerLimb = 9;
  explicit QualityMeter(const deform::BoundModel& bound);

  // sweep_method: whether posed's α/β are those of the deformation (then the sweep integral is
  // reported); for LBS/DQS pass false (the poser still gives the section planes).
  QualityMetrics measure(std::span<const glm::vec3> positions, const deform::SweepPoser& posed,
                         bool sweep_method) const;
  // The largest |l / l_rest - 1| over the welded edges (the stretch heat map's scale), without
  // the self-intersection count and the limb sections that make up most of measure's time.
  double largest_edge_stretch(std::span<const glm::vec3> positions) const;
  // The shortest and the longest edge as length ratios l / l_rest (squash, stretch): what a
  // picture's caption says, where |l / l_rest - 1| would read 2.97 for an edge 3.97x its length.
  std::pair<double, double> edge_ratio_range(std::span<const glm::vec3> positions) const;

  const deform::PartVolumeRegions& regions() const { return regions_; }
  // The welded edges one by one (metrics/region_quality.h sorts them into body regions): an
  // edge's two model vertices, and its length ratio l / l_rest (1 for a zero rest length).
  std::size_t edge_count() const { return rest_edge_length_.size(); }
  std::pair<std::uint32_t, std::uint32_t> edge_vertices(std::size_t e) const {
    return {edges_[2 * e], edges_[2 * e + 1]};
  }
  double edge_ratio(std::span<const glm::vec3> positions, std::size_t e) const;

 private:
  std::vector<glm::vec3> welded_positions(std::span<const glm::vec3> positions) const;

  const deform::BoundModel& bound_;
  deform::PartVolumeRegions regions_;
  std::vector<double> rest_mesh_volume_, rest_sweep_volume_;
  std::vector<std::uint32_t> welded_;          // per model vertex: its welded id
  std::vector<std::uint32_t> welded_indices_;  // the triangles over welded ids (closed loops)
  std::size_t welded_count_ = 0;
  std::vector<std::uint32_t> edges_;  // welded-edge endpoints as model vertices, 2 per edge
  std::vector<float> rest_edge_length_;
  std::vector<int> limb_sweeps_;
  std::vector<float> rest_section_area_;  // per limb sweep and section
};

// The parameters where limb sections are measured: evenly inside (0, 1), away from the ends.
float section_parameter(int section);

}  // namespace sweepd::metrics
