// SweptStretchMeter: the part of RegionMeter (region_quality.h) that compare_with_skinning reads,
// at a fraction of its cost — per body region, the largest length ratio l / l_rest over the
// welded edges with a swept vertex (VertexBinding::skin_weight < 1), and the triangles with a
// swept vertex that flipped. What the binding's self-check measures on every pose it plays
// (selfcheck/binding_self_check.h), where RegionMeter's creases and whole-region figures would
// cost more than binding itself.
// Inputs: the positions of the vertices it reads (vertices(): a swept body's limbs and torso,
// not its head, hands and feet) and the posed joints' world matrices.
// Output: one RegionFigures per regions() entry with swept, swept_stretch and swept_flipped set
// as RegionMeter::measure sets them (the other fields stay at their rest values); the stretch
// from squared lengths, so within a few float roundings (1e-6) of RegionMeter's.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "metrics/region_quality.h"

namespace sweepd::metrics {

class SweptStretchMeter {
 public:
  explicit SweptStretchMeter(const deform::BoundModel& bound);
  const std::vector<deform::BodyPart>& regions() const { return regions_; }
  // The model vertices it reads (those of a swept edge or triangle), ascending: measure takes
  // their positions in this order, so a caller can deform these alone.
  const std::vector<std::uint32_t>& vertices() const { return vertices_; }
  // vertices()' positions out of a whole mesh's (vertex_count()).
  void gather(std::span<const glm::vec3> positions, std::vector<glm::vec3>& measured) const;
  // positions: vertices().size(), in vertices()' order; joint_world: the posed joints' world
  // matrices. Into figures (resized to regions().size()). Const: one meter measures poses on
  // several threads at once.
  void measure(std::span<const glm::vec3> positions, std::span<const glm::mat4> joint_world,
               std::vector<RegionFigures>& figures) const;
  // The same, and per region how many swept edges are longer than kStretchedEdge times their
  // rest length (how much of the region stretches, where the figures say only how far its
  // worst edge does).
  static constexpr float kStretchedEdge = 1.3f;
  void measure(std::span<const glm::vec3> positions, std::span<const glm::mat4> joint_world,
               std::vector<RegionFigures>& figures, std::vector<int>& stretched_edges) const;
  // Two sets of positions in one pose (the self-check's LBS and DQS), each measured as measure
  // measures it, to the bit: the items' vertices and rest lengths, and the rest normals turned
  // into the pose, are read and computed once for both.
  void measure_two(std::span<const glm::vec3> first, std::span<const glm::vec3> second,
                   std::span<const glm::mat4> joint_world,
                   std::vector<RegionFigures>& first_figures,
                   std::vector<RegionFigures>& second_figures) const;

  // The two model vertices of region `region`'s edge with the largest ratio l / l_rest in these
  // positions (as measure takes them; the first such edge where several tie); none where the
  // region has no edge here.
  std::optional<std::array<std::uint32_t, 2>> longest_edge(std::span<const glm::vec3> positions,
                                                           int region) const;

  // The regions with an edge or triangle that has a vertex flagged in `moving` (one flag per
  // model vertex): the regions whose figures change when those vertices move alone.
  std::vector<std::uint8_t> regions_touched(std::span<const std::uint8_t> moving) const;
  // The same meter over part of its edges and triangles in those regions: with `touching`, the
  // ones with a flagged vertex, else the others. Its regions and their swept flags are the whole
  // meter's; in a touched region the two parts' figures combine into the whole's (combine), and
  // a region not touched is in neither part (its figures are the caller's to keep): what a
  // caller that moves the flagged vertices alone measures again.
  SweptStretchMeter part(std::span<const std::uint8_t> moving, bool touching) const;
  // Into figures and stretched_edges (one part's), the other part's: the larger stretch, the
  // flipped triangles and stretched edges summed.
  static void combine(std::vector<RegionFigures>& figures, std::vector<int>& stretched_edges,
                      const std::vector<RegionFigures>& other_figures,
                      const std::vector<int>& other_stretched_edges);

 private:
  SweptStretchMeter() = default;
  // measure and measure_two: K sets of positions at once.
  template <std::size_t K>
  void measure_sets(const std::array<std::span<const glm::vec3>, K>& positions,
                    std::span<const glm::mat4> joint_world,
                    const std::array<std::vector<RegionFigures>*, K>& figures,
                    const std::array<std::vector<int>*, K>& stretched_edges) const;
  // Edge e's squared length ratio (l / l_rest)² in positions (vertices_' order).
  float squared_ratio(std::span<const glm::vec3> positions, std::uint32_t e) const {
    const glm::vec3 d = positions[edges_[2 * e]] - positions[edges_[2 * e + 1]];
    return glm::dot(d, d) * inverse_squared_rest_[e];
  }
  // Orders the edges and the triangles by region (measure takes a region's items in one run).
  void group_by_region();
  // edge_first_ and triangle_first_ of items grouped by region.
  void index_regions();
  std::vector<deform::BodyPart> regions_;
  std::vector<bool> region_swept_;          // per region: it has a swept edge
  std::vector<std::uint32_t> vertices_;     // the model vertices read, ascending
  // Below, vertices are numbered in vertices_' order.
  std::vector<std::uint32_t> edges_;        // 2 per swept welded edge of positive rest length
  std::vector<float> inverse_squared_rest_; // per such edge: 1 / l_rest²
  std::vector<int> edge_region_;            // per such edge
  // 3 per triangle with a swept vertex, once per region it counts in (triangle_regions)
  std::vector<std::uint32_t> triangles_;
  std::vector<int> triangle_region_;        // per such triangle
  std::vector<int> triangle_joints_;        // 3 per such triangle: its corners' strongest joints
  std::vector<glm::vec3> rest_normal_;      // per such triangle (unnormalised)
  std::vector<glm::mat4> inverse_rest_;     // per joint
  // Edges and triangles are grouped by region: region r's are [first[r], first[r + 1]).
  std::vector<std::uint32_t> edge_first_, triangle_first_;
};

}  // namespace sweepd::metrics
