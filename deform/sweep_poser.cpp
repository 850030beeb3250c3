#include "deform/sweep_poser.h"

#include <array>
#include <cmath>

#include "deform/bind.h"
#include "deform/key_posing.h"
#include "deform/mesh_topology.h"
#include "deform/sweep_coordinates.h"
#include "deform/vertex_blocks.h"

namespace sweepd::deform {

namespace {

glm::quat rotation_of(const glm::mat4& m) {
  return glm::normalize(glm::quat_cast(glm::mat3(glm::normalize(glm::vec3(m[0])),
                                                 glm::normalize(glm::vec3(m[1])),
                                                 glm::normalize(glm::vec3(m[2])))));
}

glm::vec3 skinned_position(const Model& model, std::span<const glm::mat4> skinning, std::size_t v) {
  const glm::vec4 rest(model.positions[v], 1.0f);
  glm::vec3 p(0.0f);
  for (int k = 0; k < kInfluences; ++k)
    p += model.skin_weights[v][k] * glm::vec3(skinning[model.skin_joints[v][k]] * rest);
  return p;
}

}  // namespace

SweepPoser::SweepPoser(const BoundModel& bound) : bound_(bound) {
  const Skeleton& skeleton = bound.model.skeleton;
  const std::vector<glm::mat4> world_rest = skeleton.world_rest_matrices();
  for (const glm::mat4& m : world_rest) {
    rest_rotation_inverse_.push_back(glm::inverse(rotation_of(m)));
    rest_joint_.emplace_back(m[3]);
  }
  joint_rotation_.resize(world_rest.size());
  pose_joint_ = rest_joint_;

  for (const BoundSweep& sweep : bound.sweeps) {
    sweeps_.push_back(rest_sweep(sweep, bound.options));
    posed_keys_.push_back(sweep.rest_keys);
    frame_.emplace_back();
  }

  const std::size_t n = bound.model.vertex_count();
  first_binding_.assign(n + 1, 0);
  for (std::size_t v = 0; v < n; ++v) {
    const VertexBinding& vb = bound.vertices[v];
    for (int k = 0; k < 2; ++k) {
      if (vb.sweep[k] < 0 || vb.weight[k] == 0.0f) continue;
      const Sweep& sweep = sweeps_[vb.sweep[k]];
      const SweepCoordinate& c = vb.coordinate[k];
      Binding b{};
      b.sweep = static_cast<std::uint16_t>(vb.sweep[k]);
      b.weight = vb.weight[k];
      const auto spline = sweep.centre_curve().weights(c.t);
      b.span = static_cast<std::uint16_t>(spline.span);
      for (int r = 0; r < 4; ++r) b.spline[r] = static_cast<float>(spline.w[r]);
      const auto t = sweep.parameters();
      b.q_mix = static_cast<float>((c.t - t[spline.span]) / (t[spline.span + 1] - t[spline.span]));
      std::array<double, InterpolatingQuadraticSpline::kMaxDegree + 1> basis{};
      b.axis_first = static_cast<std::uint16_t>(sweep.a_function().nonzero_basis(c.t, basis));
      for (int r = 0; r < 3; ++r)
        b.axis[r] = r <= sweep.a_function().degree() ? static_cast<float>(basis[r]) : 0.0f;
      b.cos_theta = std::cos(c.theta);
      b.sin_theta = std::sin(c.theta);
      b.da = c.da;
      b.db = c.db;
      b.c = c.c;
      bindings_.push_back(b);
    }
    first_binding_[v + 1] = static_cast<std::uint32_t>(bindings_.size());
  }

  std::size_t welded_count = 0;
  welded_ = weld_coincident_positions(bound.model.positions, &welded_count);
  welded_normals_.resize(welded_count);
  refresh_half_axes();
  std::vector<glm::mat4> rest(world_rest);
  set_pose(rest);
}

void SweepPoser::refresh_half_axes() {
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    SweepFrameData& f = frame_[s];
    f.alpha.assign(sweeps_[s].alpha().begin(), sweeps_[s].alpha().end());
    f.beta.assign(sweeps_[s].beta().begin(), sweeps_[s].beta().end());
    f.alpha.resize(f.alpha.size() + 2, 0.0f);
    f.beta.resize(f.beta.size() + 2, 0.0f);
  }
}

void SweepPoser::set_pose(std::span<const glm::mat4> world_pose) {
  for (std::size_t j = 0; j < world_pose.size(); ++j) {
    joint_rotation_[j] = rotation_of(world_pose[j]) * rest_rotation_inverse_[j];
    pose_joint_[j] = glm::vec3(world_pose[j][3]);
  }
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    pose_key_ellipses(bound_.sweeps[s], bound_.model.skeleton, joint_rotation_, rest_joint_,
                      pose_joint_, posed_keys_[s]);
    sweeps_[s].set_key_frames(posed_keys_[s]);
    SweepFrameData& f = frame_[s];
    const auto& curve = sweeps_[s].centre_curve();
    f.points.assign(curve.points().begin(), curve.points().end());
    f.second.assign(curve.span_second_derivatives().begin(), curve.span_second_derivatives().end());
    f.keys.assign(sweeps_[s].orientation_curve().keys().begin(),
                  sweeps_[s].orientation_curve().keys().end());
  }
}

void SweepPoser::deform_block(std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
                              std::size_t begin, std::size_t end) const {
  const Model& model = bound_.model;
  for (std::size_t v = begin; v < end; ++v) {
    const float skin = bound_.vertices[v].skin_weight;
    glm::vec3 p = skin > 0.0f ? skin * skinned_position(model, skinning, v) : glm::vec3(0.0f);
    for (std::uint32_t i = first_binding_[v]; i < first_binding_[v + 1]; ++i) {
      const Binding& b = bindings_[i];
      const SweepFrameData& f = frame_[b.sweep];
      const int s = b.span;
      const glm::vec3 centre = b.spline[0] * f.points[s] + b.spline[1] * f.points[s + 1] +
                               b.spline[2] * f.second[2 * s] + b.spline[3] * f.second[2 * s + 1];
      const glm::quat q =
          glm::normalize((1.0f - b.q_mix) * f.keys[s] + b.q_mix * f.keys[s + 1]);
      const int a0 = b.axis_first;
      const float a = b.axis[0] * f.alpha[a0] + b.axis[1] * f.alpha[a0 + 1] +
                      b.axis[2] * f.alpha[a0 + 2];
      const float bb = b.axis[0] * f.beta[a0] + b.axis[1] * f.beta[a0 + 1] +
                       b.axis[2] * f.beta[a0 + 2];
      const glm::vec3 local((a + b.da) * b.cos_theta, (bb + b.db) * b.sin_theta, b.c);
      p += b.weight * (centre + glm::mat3_cast(q) * local);
    }
    positions[v] = p;
  }
}

void SweepPoser::deform(std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
                        std::span<glm::vec3> normals, int threads) {
  run_in_vertex_blocks(bound_.model.vertex_count(), threads,
                       [&](std::size_t begin, std::size_t end) {
                         deform_block(skinning, positions, begin, end);
                       });
  if (!normals.empty()) compute_normals(positions, normals);
}

void SweepPoser::compute_normals(std::span<const glm::vec3> positions,
                                 std::span<glm::vec3> normals) {
  std::fill(welded_normals_.begin(), welded_normals_.end(), glm::vec3(0.0f));
  const auto& indices = bound_.model.indices;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::vec3& a = positions[indices[t]];
    const glm::vec3 area_normal = glm::cross(positions[indices[t + 1]] - a, positions[indices[t + 2]] - a);
    for (int k = 0; k < 3; ++k) welded_normals_[welded_[indices[t + k]]] += area_normal;
  }
  for (glm::vec3& n : welded_normals_) {
    const float length = glm::length(n);
    n = length > 0.0f ? n / length : glm::vec3(0, 1, 0);
  }
  for (std::size_t v = 0; v < normals.size(); ++v) normals[v] = welded_normals_[welded_[v]];
}

glm::vec3 SweepPoser::reference_position(std::size_t v, std::span<const glm::mat4> skinning) const {
  const VertexBinding& vb = bound_.vertices[v];
  glm::vec3 p = vb.skin_weight * skinned_position(bound_.model, skinning, v);
  for (int k = 0; k < 2; ++k)
    if (vb.sweep[k] >= 0) p += vb.weight[k] * evaluate_point(sweeps_[vb.sweep[k]], vb.coordinate[k]);
  return p;
}

}  // namespace sweepd::deform
