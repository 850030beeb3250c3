// SweepPoser: the per-frame sweep deformation of a bound model (paper §4.1) — the fast path.
//
// set_pose: world joint matrices → posed key ellipses → each sweep's C(t) and Q(t) rebuilt
//   (a(t), b(t) stay; volume correction and edits change them through sweep()).
// deform: every vertex from its binding, V = Σ_k w_k [C_k(t) + R_k(t) ((a+da) cos θ,
//   (b+db) sin θ, c)] + w_skin · LBS(V), blended where two sweeps meet.
// Speed: t_V is fixed per vertex, so at construction each binding stores the weights that
//   make C(t_V) a fixed combination of the spline's data (InterpolatingCubicSpline::weights),
//   the factor of its Q(t) span and the quadratic basis of a(t), b(t), plus cos θ and sin θ.
//   A frame then costs a few dozen flops per binding, nothing is allocated, and the result
//   equals the direct evaluation (reference_position) up to float rounding.
// Threads: deform(…, threads) splits the vertices into blocks; results are bit-identical for
//   any thread count.
// The BoundModel must outlive the poser.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <vector>

#include "deform/bound_model.h"
#include "deform/sweep.h"

namespace sweepd::deform {

class SweepPoser {
 public:
  explicit SweepPoser(const BoundModel& bound);

  // world_pose: skeleton.size() world joint matrices (forward_kinematics).
  void set_pose(std::span<const glm::mat4> world_pose);

  // skinning: skeleton.size() skinning matrices of the same pose (for the skinned share).
  // positions: vertex_count() outputs; normals: vertex_count() area-weighted unit normals
  // (seam copies share them), or empty to skip.
  void deform(std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
              std::span<glm::vec3> normals, int threads = 1);

  // One vertex evaluated directly through Sweep (double-precision curves): the reference.
  glm::vec3 reference_position(std::size_t vertex, std::span<const glm::mat4> skinning) const;

  int sweep_count() const { return static_cast<int>(sweeps_.size()); }
  const Sweep& sweep(int s) const { return sweeps_[s]; }
  Sweep& sweep(int s) { return sweeps_[s]; }
  std::span<const KeyEllipse> posed_keys(int s) const { return posed_keys_[s]; }
  // Call after changing a sweep's α/β (volume correction) so deform sees them.
  void refresh_half_axes();

 private:
  struct Binding {  // one (vertex, sweep) term, everything fixed at construction
    std::uint16_t sweep;
    std::uint16_t span;        // key span of C and Q
    std::uint16_t axis_first;  // first of the 3 quadratic basis functions of a, b
    float weight;
    float spline[4];  // C(t) = spline · (P_span, P_span+1, P''_span, P''_span+1)
    float q_mix;      // Q(t) = (1 - q_mix) q_span + q_mix q_span+1
    float axis[3];    // a(t) = Σ axis[r] α_{axis_first + r}
    float cos_theta, sin_theta, da, db, c;
  };
  struct SweepFrameData {  // per frame, float copies of each sweep's curve data
    std::vector<glm::vec3> points, second;
    std::vector<glm::quat> keys;
    std::vector<float> alpha, beta;  // padded with zeros for degree < 2
  };

  void deform_block(std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
                    std::size_t begin, std::size_t end) const;
  void compute_normals(std::span<const glm::vec3> positions, std::span<glm::vec3> normals);

  const BoundModel& bound_;
  std::vector<Sweep> sweeps_;
  std::vector<std::vector<KeyEllipse>> posed_keys_;
  std::vector<SweepFrameData> frame_;
  std::vector<std::uint32_t> first_binding_;  // CSR: bindings of vertex v are [first[v], first[v+1])
  std::vector<Binding> bindings_;
  std::vector<glm::quat> rest_rotation_inverse_, joint_rotation_;
  std::vector<glm::vec3> rest_joint_, pose_joint_;
  std::vector<std::uint32_t> welded_;  // welded id per vertex, for seam-consistent normals
  std::vector<glm::vec3> welded_normals_;
};

}  // namespace sweepd::deform
