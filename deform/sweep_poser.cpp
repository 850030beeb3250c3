#include "deform/sweep_poser.h"

#include <algorithm>
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

// LBS of one vertex: blend the four matrices' columns, then one transform (as LBS does).
glm::vec3 skinned_position(const Model& model, std::span<const glm::mat4> skinning, std::size_t v) {
  const auto& w = model.skin_weights[v];
  const auto& j = model.skin_joints[v];
  const glm::mat4 m = skinning[j[0]] * w[0] + skinning[j[1]] * w[1] + skinning[j[2]] * w[2] +
                      skinning[j[3]] * w[3];
  const glm::vec3 p = model.positions[v];
  return glm::vec3(m[0]) * p.x + glm::vec3(m[1]) * p.y + glm::vec3(m[2]) * p.z + glm::vec3(m[3]);
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

  // Table rows: kSamplesPerSpan per key span, aligned with the keys, plus the last key.
  for (const BoundSweep& sweep : bound.sweeps) {
    sweeps_.push_back(rest_sweep(sweep, bound.options));
    posed_keys_.push_back(sweep.rest_keys);
    sweep_data_.emplace_back();
    first_sample_.push_back(static_cast<std::uint32_t>(sample_weights_.size()));
    const Sweep& curve = sweeps_.back();
    const auto t = curve.parameters();
    for (std::size_t i = 0; i + 1 < t.size(); ++i)
      for (int k = 0; k <= kSamplesPerSpan; ++k) {
        if (k == kSamplesPerSpan && i + 2 < t.size()) break;  // the next span's first row
        const double at = t[i] + (t[i + 1] - t[i]) * k / kSamplesPerSpan;
        SampleWeights w{};
        w.sweep = static_cast<std::uint16_t>(sweeps_.size() - 1);
        w.span = static_cast<std::uint16_t>(i);
        const auto spline = curve.centre_curve().weights(at);
        for (int r = 0; r < 4; ++r) w.spline[r] = static_cast<float>(spline.w[r]);
        w.span = static_cast<std::uint16_t>(spline.span);
        w.q_mix = static_cast<float>((at - t[spline.span]) / (t[spline.span + 1] - t[spline.span]));
        std::array<double, InterpolatingQuadraticSpline::kMaxDegree + 1> basis{};
        w.axis_first = static_cast<std::uint16_t>(curve.a_function().nonzero_basis(at, basis));
        for (int r = 0; r < 3; ++r)
          w.axis[r] = r <= curve.a_function().degree() ? static_cast<float>(basis[r]) : 0.0f;
        sample_weights_.push_back(w);
        sample_offset_.push_back(curve.offset(static_cast<float>(at)));
      }
  }
  table_.resize(sample_weights_.size());

  const std::size_t n = bound.model.vertex_count();
  first_binding_.assign(n + 1, 0);
  skin_weight_.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    const VertexBinding& vb = bound.vertices[v];
    skin_weight_[v] = vb.skin_weight;
    for (int k = 0; k < kSweepsPerVertex; ++k) {
      if (vb.sweep[k] < 0 || vb.weight[k] == 0.0f) continue;
      const SweepCoordinate& c = vb.coordinate[k];
      // The row at or below t (the last row's predecessor at t = 1), and the fraction past it.
      const auto t = sweeps_[vb.sweep[k]].parameters();
      const std::size_t span = std::min<std::size_t>(
          std::upper_bound(t.begin() + 1, t.end() - 1, static_cast<double>(c.t)) - t.begin() - 1,
          t.size() - 2);
      const double within = (c.t - t[span]) / (t[span + 1] - t[span]) * kSamplesPerSpan;
      const int step = std::clamp(static_cast<int>(within), 0, kSamplesPerSpan - 1);
      Binding b{};
      b.sample = first_sample_[vb.sweep[k]] + static_cast<std::uint32_t>(span * kSamplesPerSpan + step);
      b.fraction = static_cast<float>(within - step);
      b.weight = vb.weight[k];
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
  set_pose(world_rest);
}

void SweepPoser::refresh_table() {
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    SweepData& d = sweep_data_[s];
    const Sweep& sweep = sweeps_[s];
    const auto& curve = sweep.centre_curve();
    d.points.assign(curve.points().begin(), curve.points().end());
    d.second.assign(curve.span_second_derivatives().begin(), curve.span_second_derivatives().end());
    d.keys.assign(sweep.orientation_curve().keys().begin(), sweep.orientation_curve().keys().end());
    d.alpha.assign(sweep.alpha().begin(), sweep.alpha().end());
    d.beta.assign(sweep.beta().begin(), sweep.beta().end());
    d.alpha.resize(d.alpha.size() + 2, 0.0f);
    d.beta.resize(d.beta.size() + 2, 0.0f);
  }
  for (std::size_t row = 0; row < table_.size(); ++row) {
    const SampleWeights& w = sample_weights_[row];
    const SweepData& d = sweep_data_[w.sweep];
    const int i = w.span, k = w.axis_first;
    const glm::vec3 centre = w.spline[0] * d.points[i] + w.spline[1] * d.points[i + 1] +
                             w.spline[2] * d.second[2 * i] + w.spline[3] * d.second[2 * i + 1];
    const glm::mat3 r = glm::mat3_cast(
        glm::normalize((1.0f - w.q_mix) * d.keys[i] + w.q_mix * d.keys[i + 1]));
    const float a = w.axis[0] * d.alpha[k] + w.axis[1] * d.alpha[k + 1] + w.axis[2] * d.alpha[k + 2];
    const float b = w.axis[0] * d.beta[k] + w.axis[1] * d.beta[k + 1] + w.axis[2] * d.beta[k + 2];
    const glm::vec3 ellipse_centre = centre + r * glm::vec3(sample_offset_[row], 0.0f);  // C̃
    table_[row] = {ellipse_centre, a, r[0], b, r[1], 0.0f, r[2], 0.0f};
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
    if (key_adjuster_) key_adjuster_(static_cast<int>(s), posed_keys_[s]);
    sweeps_[s].set_key_frames(posed_keys_[s]);
    sweeps_[s].set_key_half_axes(posed_keys_[s]);
  }
  refresh_table();
}

void SweepPoser::deform_block(std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
                              std::size_t begin, std::size_t end) const {
  const Model& model = bound_.model;
  const Sample* table = table_.data();
  for (std::size_t v = begin; v < end; ++v) {
    const float skin = skin_weight_[v];
    glm::vec3 p = skin > 0.0f ? skin * skinned_position(model, skinning, v) : glm::vec3(0.0f);
    for (std::uint32_t i = first_binding_[v]; i < first_binding_[v + 1]; ++i) {
      const Binding& b = bindings_[i];
      const Sample& s0 = table[b.sample];
      const Sample& s1 = table[b.sample + 1];
      const float f = b.fraction;
      const float x = (s0.a + f * (s1.a - s0.a) + b.da) * b.cos_theta;
      const float y = (s0.b + f * (s1.b - s0.b) + b.db) * b.sin_theta;
      const glm::vec3 at0 = s0.centre + x * s0.x_axis + y * s0.y_axis + b.c * s0.normal;
      const glm::vec3 at1 = s1.centre + x * s1.x_axis + y * s1.y_axis + b.c * s1.normal;
      p += b.weight * (at0 + f * (at1 - at0));
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
  for (int k = 0; k < kSweepsPerVertex; ++k)
    if (vb.sweep[k] >= 0) p += vb.weight[k] * evaluate_point(sweeps_[vb.sweep[k]], vb.coordinate[k]);
  return p;
}

}  // namespace sweepd::deform
