// SweepPoser: the per-frame sweep deformation of a bound model (paper §4.1) — the fast path.
//
// set_pose: world joint matrices → posed key ellipses → (the key adjuster, if set: edits,
//   muscle bulge) → each sweep's C(t), Q(t), a(t) and b(t) rebuilt from the keys (so a volume
//   correction of the previous frame does not carry over; it changes α, β through sweep()
//   after set_pose, followed by refresh_table()).
// deform: every vertex from its binding, V = Σ_k w_k [C̃_k(t) + R_k(t) ((a+da) cos θ,
//   (b+db) sin θ, c)] + w_skin · LBS(V), blended where two sweeps meet (C̃: the ellipse's
//   centre, Sweep::ellipse_centre).
// Speed: per frame each sweep is evaluated once at a table of samples (kSamplesPerSpan per key
//   span, aligned with the keys): C̃, R (as 3 columns), a, b; the rows of one span are filled by
//   one vectorised loop. t_V is fixed per vertex, so each binding keeps its sample index and
//   fraction, cos θ and sin θ; a sweep term then costs two table rows combined with θ and a
//   linear interpolation; the terms are evaluated eight at a time, batched by row, and a vertex
//   with several terms or a skinned share adds up its terms' points (sweep_vertex_kinds.h).
//   Where a key span turns its plane too sharply for the skin bound to it, the table's rows
//   are turned to spread the bend (plane_turn_limit.h); the reference
//   evaluation turns its frame by the same rows' turns. The vertices are grouped by kind
//   (SweepVertexKinds: skin influences × sweep terms) so each group runs a loop without branches,
//   and the skinned share transforms the rest position by each influence's matrix (cheaper than
//   blending the matrices for 1–3 influences). Nothing is allocated, and the result matches the
//   direct evaluation (reference_position) within 1e-5 × height (9.1e-6 m on the shared
//   male, 7.5e-6 m before the ellipses' offsets: R interpolated between samples 1/64 of a span
//   apart).
// Threads: deform(…, threads) splits the vertices into blocks; results are bit-identical for
//   any thread count.
// What never changes for a model (rest sweeps, the table's layout, the vertex kinds, the
// welded-normals topology) is in SweepPoserTables (sweep_poser_tables.h), shared by every poser
// of the model; a poser holds only one frame's state (the posed keys and sweeps, the sample
// table, the normal sums). The BoundModel must outlive the poser.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/posing/sweep_poser_tables.h"
#include "deform/sweep/sweep.h"

namespace sweepd::deform {

class SweepPoser {
 public:
  // instructions: what the vertex loops run on (SweepVertexKinds); the widest the CPU has by
  // default.
  explicit SweepPoser(const BoundModel& bound,
                      VertexLoopInstructions instructions = widest_vertex_loop_instructions());
  // A poser on tables built once for the model (make_sweep_poser_tables).
  explicit SweepPoser(std::shared_ptr<const SweepPoserTables> tables);

  // world_pose: skeleton.size() world joint matrices (forward_kinematics).
  void set_pose(std::span<const glm::mat4> world_pose);

  // skinning: skeleton.size() skinning matrices of the same pose (for the skinned share).
  // positions: vertex_count() outputs; normals: vertex_count() area-weighted unit normals
  // (seam copies share them), or empty to skip.
  void deform(std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
              std::span<glm::vec3> normals, int threads = 1);

  // One vertex evaluated directly through Sweep (double-precision curves): the reference.
  glm::vec3 reference_position(std::size_t vertex, std::span<const glm::mat4> skinning) const;
  // The point of sweep s at a binding coordinate, and its plane's normal at t, as the reference
  // evaluates them: the sweep's frame turned as the table's rows around t were
  // (plane_turn_limit.h).
  glm::vec3 reference_point(int s, const SweepCoordinate& coordinate) const;
  glm::vec3 reference_normal(int s, float t) const;

  // The last frame's sample table (SweepSample rows, as the vertex loops read them) and the
  // model's tables (which row a binding reads: sample_row_of).
  std::span<const SweepSample> sample_table() const { return table_; }
  const SweepPoserTables& tables() const { return *tables_; }

  int sweep_count() const { return static_cast<int>(sweeps_.size()); }
  const Sweep& sweep(int s) const { return sweeps_[s]; }
  Sweep& sweep(int s) { return sweeps_[s]; }
  std::span<const KeyEllipse> posed_keys(int s) const { return posed_keys_[s]; }
  // Call after changing a sweep's α/β (volume correction) so deform sees them.
  void refresh_table();
  // Whether the last table turned sweep s's rows to keep its planes from crossing in the skin
  // (plane_turn_limit.h).
  bool plane_turns_limited(int s) const { return sweep_turned_[s] != 0; }

  // Called by set_pose for every sweep with its posed keys, before the sweep is rebuilt from
  // them: edits and muscle bulge change centres, orientations and half-axes here. Empty: none.
  using KeyAdjuster = std::function<void(int sweep, std::span<KeyEllipse> keys)>;
  void set_key_adjuster(KeyAdjuster adjuster) { key_adjuster_ = std::move(adjuster); }
  // World rotation deltas (pose · rest⁻¹) of the joints in the last pose.
  std::span<const glm::quat> joint_rotations() const { return joint_rotation_; }

 private:
  glm::mat3 row_turn_at(int s, float t) const;  // identity where the sweep was not turned

  struct SweepData {  // per frame, float copies of a sweep's curve data
    std::vector<glm::vec3> points, second;
    std::vector<glm::quat> keys;
    // Per control: (α, β, offset x, offset y), one vector so a row's four are one weighted sum;
    // padded with zeros for a degree below 2.
    std::vector<glm::vec4> axis_controls;
  };

  std::shared_ptr<const SweepPoserTables> tables_;
  const BoundModel& bound_;
  KeyAdjuster key_adjuster_;
  std::vector<Sweep> sweeps_;
  std::vector<std::vector<KeyEllipse>> posed_keys_;
  std::vector<SweepData> sweep_data_;  // per sweep
  std::vector<SweepSample> table_;     // per frame: every sweep at its samples
  // Per frame: per row, the turn the plane turn limit gave it (plane_turn_limit.h), and per
  // sweep whether it turned any (the rows of a sweep that did not hold stale values).
  std::vector<glm::quat> row_turn_;
  std::vector<char> sweep_turned_;
  PlaneTurnScratch turn_scratch_;
  std::vector<glm::quat> joint_rotation_;
  std::vector<glm::vec3> pose_joint_;
  std::vector<FloatLanes> normal_sums_;
  std::vector<float> term_lanes_;  // per frame: the junction vertices' terms (SweepVertexKinds)
};

}  // namespace sweepd::deform
