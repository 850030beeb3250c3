#include "deform/posing/sweep_poser.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "deform/binding/rest_sweep.h"
#include "deform/binding/sweep_coordinates.h"
#include "deform/posing/key_posing.h"
#include "deform/simd/vertex_blocks.h"

namespace sweepd::deform {

namespace {

glm::quat rotation_of(const glm::mat4& m) {
  return glm::normalize(
      glm::quat_cast(glm::mat3(glm::normalize(glm::vec3(m[0])), glm::normalize(glm::vec3(m[1])),
                               glm::normalize(glm::vec3(m[2])))));
}

// The influences the skinned share follows: the binding's own, else the model's.
std::span<const std::array<std::uint16_t, kInfluences>> skinned_share_joints(
    const BoundModel& bound) {
  return bound.skinned_share_joints.empty() ? bound.model.skin_joints : bound.skinned_share_joints;
}
std::span<const std::array<float, kInfluences>> skinned_share_weights(const BoundModel& bound) {
  return bound.skinned_share_weights.empty() ? bound.model.skin_weights
                                             : bound.skinned_share_weights;
}

// LBS of one vertex's skinned share: blend the four matrices' columns, then one transform (as
// LBS does).
glm::vec3 skinned_position(const BoundModel& bound, std::span<const glm::mat4> skinning,
                           std::size_t v) {
  const Model& model = bound.model;
  const auto& w = skinned_share_weights(bound)[v];
  const auto& j = skinned_share_joints(bound)[v];
  const glm::mat4 m =
      skinning[j[0]] * w[0] + skinning[j[1]] * w[1] + skinning[j[2]] * w[2] + skinning[j[3]] * w[3];
  const glm::vec3 p = model.positions[v];
  return glm::vec3(m[0]) * p.x + glm::vec3(m[1]) * p.y + glm::vec3(m[2]) * p.z + glm::vec3(m[3]);
}

}  // namespace

SweepPoser::SweepPoser(const BoundModel& bound, VertexLoopInstructions instructions)
    : bound_(bound), normals_(bound.model.positions, bound.model.indices) {
  const Skeleton& skeleton = bound.model.skeleton;
  const std::vector<glm::mat4> world_rest = skeleton.world_rest_matrices();
  for (const glm::mat4& m : world_rest) {
    rest_rotation_inverse_.push_back(glm::inverse(rotation_of(m)));
    rest_joint_.emplace_back(m[3]);
  }
  joint_rotation_.resize(world_rest.size());
  pose_joint_ = rest_joint_;

  // Table rows: kSamplesPerSpan per key span, aligned with the keys, plus the last key.
  std::vector<std::uint32_t> first_sample;  // per sweep: its first row in table_
  for (const BoundSweep& sweep : bound.sweeps) {
    sweeps_.push_back(rest_sweep(sweep, bound.options));
    posed_keys_.push_back(sweep.rest_keys);
    mitre_spread_.push_back(mitre_spread(sweep));
    sweep_data_.emplace_back();
    first_sample.push_back(static_cast<std::uint32_t>(sample_q_mix_.size()));
    const Sweep& curve = sweeps_.back();
    const auto t = curve.parameters();
    for (std::size_t i = 0; i + 1 < t.size(); ++i)
      for (int k = 0; k <= kSamplesPerSpan; ++k) {
        if (k == kSamplesPerSpan && i + 2 < t.size()) break;  // the next span's first row
        const double at = t[i] + (t[i + 1] - t[i]) * k / kSamplesPerSpan;
        const auto spline = curve.centre_curve().weights(at);
        const auto row = static_cast<std::uint32_t>(sample_q_mix_.size());
        const auto sweep_index = static_cast<std::uint16_t>(sweeps_.size() - 1);
        const auto span = static_cast<std::uint16_t>(spline.span);
        if (sample_runs_.empty() || sample_runs_.back().sweep != sweep_index ||
            sample_runs_.back().span != span)
          sample_runs_.push_back({row, row, sweep_index, span});
        ++sample_runs_.back().end;
        for (int r = 0; r < 4; ++r) sample_spline_[r].push_back(static_cast<float>(spline.w[r]));
        sample_q_mix_.push_back(
            static_cast<float>((at - t[spline.span]) / (t[spline.span + 1] - t[spline.span])));
        std::array<double, InterpolatingQuadraticSpline::kMaxDegree + 1> basis{};
        SampleAxisWeights axis{};
        axis.first = static_cast<std::uint32_t>(curve.a_function().nonzero_basis(at, basis));
        for (int r = 0; r < 3; ++r)
          axis.axis[r] = r <= curve.a_function().degree() ? static_cast<float>(basis[r]) : 0.0f;
        sample_axis_.push_back(axis);
      }
  }
  table_.resize(sample_q_mix_.size());

  const std::size_t n = bound.model.vertex_count();
  std::vector<std::uint32_t> first_term(n + 1, 0);
  std::vector<float> skin_share(n);
  std::vector<SweepTerm> terms;
  for (std::size_t v = 0; v < n; ++v) {
    const VertexBinding& vb = bound.vertices[v];
    skin_share[v] = vb.skin_weight;
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
      SweepTerm term{};
      term.row =
          first_sample[vb.sweep[k]] + static_cast<std::uint32_t>(span * kSamplesPerSpan + step);
      term.fraction = static_cast<float>(within - step);
      term.weight_below = vb.weight[k] * (1.0f - term.fraction);
      term.weight_above = vb.weight[k] * term.fraction;
      term.cos_theta = std::cos(c.theta);
      term.sin_theta = std::sin(c.theta);
      term.x_shift = c.da * term.cos_theta;
      term.y_shift = c.db * term.sin_theta;
      term.c = c.c;
      terms.push_back(term);
    }
    first_term[v + 1] = static_cast<std::uint32_t>(terms.size());
  }
  vertex_kinds_.emplace(bound.model, skinned_share_joints(bound), skinned_share_weights(bound),
                        skin_share, first_term, terms, instructions);

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
    auto padded = [](std::vector<float>& out, std::span<const double> controls) {
      out.assign(controls.begin(), controls.end());
      out.resize(out.size() + 2, 0.0f);
    };
    padded(d.alpha, sweep.alpha());
    padded(d.beta, sweep.beta());
    padded(d.offset_x, sweep.offset_x_function().controls());
    padded(d.offset_y, sweep.offset_y_function().controls());
  }
  // Centre and frame: one loop per run of rows on the same span, over the rows' weights only
  // (the span's points and keys are loop constants), so it vectorises.
  SweepSample* table = table_.data();
  const float* w0 = sample_spline_[0].data();
  const float* w1 = sample_spline_[1].data();
  const float* w2 = sample_spline_[2].data();
  const float* w3 = sample_spline_[3].data();
  const float* q_mix = sample_q_mix_.data();
  for (const SampleRun& run : sample_runs_) {
    const SweepData& d = sweep_data_[run.sweep];
    const int i = run.span;
    const glm::vec3 p0 = d.points[i], p1 = d.points[i + 1];
    const glm::vec3 s0 = d.second[2 * i], s1 = d.second[2 * i + 1];
    const glm::quat q0 = d.keys[i], q1 = d.keys[i + 1];
    for (std::uint32_t row = run.begin; row < run.end; ++row) {
      SweepSample& out = table[row];
      out.centre = w0[row] * p0 + w1[row] * p1 + w2[row] * s0 + w3[row] * s1;
      // R(q / |q|) from q = (1 - m) q0 + m q1 without normalising q: 2 / |q|² scales the products.
      const float m = q_mix[row], keep = 1.0f - m;
      const float x = keep * q0.x + m * q1.x, y = keep * q0.y + m * q1.y;
      const float z = keep * q0.z + m * q1.z, w = keep * q0.w + m * q1.w;
      const float scale = 2.0f / (x * x + y * y + z * z + w * w);
      const float xx = scale * x * x, yy = scale * y * y, zz = scale * z * z;
      const float xy = scale * x * y, xz = scale * x * z, yz = scale * y * z;
      const float wx = scale * w * x, wy = scale * w * y, wz = scale * w * z;
      out.x_axis = glm::vec3(1.0f - (yy + zz), xy + wz, xz - wy);
      out.y_axis = glm::vec3(xy - wz, 1.0f - (xx + zz), yz + wx);
      out.normal = glm::vec3(xz + wy, yz - wx, 1.0f - (xx + yy));
    }
  }
  for (const SampleRun& run : sample_runs_) {
    const SweepData& d = sweep_data_[run.sweep];
    for (std::uint32_t row = run.begin; row < run.end; ++row) {
      const SampleAxisWeights& w = sample_axis_[row];
      const std::uint32_t k = w.first;
      table[row].a =
          w.axis[0] * d.alpha[k] + w.axis[1] * d.alpha[k + 1] + w.axis[2] * d.alpha[k + 2];
      table[row].b = w.axis[0] * d.beta[k] + w.axis[1] * d.beta[k + 1] + w.axis[2] * d.beta[k + 2];
      // The ellipse's centre C + R (o, 0) (KeyEllipse::offset).
      const float ox =
          w.axis[0] * d.offset_x[k] + w.axis[1] * d.offset_x[k + 1] + w.axis[2] * d.offset_x[k + 2];
      const float oy =
          w.axis[0] * d.offset_y[k] + w.axis[1] * d.offset_y[k + 1] + w.axis[2] * d.offset_y[k + 2];
      table[row].centre += ox * table[row].x_axis + oy * table[row].y_axis;
    }
  }
  // A sweep's last row gets the next sweep's first row: no term starts there.
  for (std::size_t row = 0; row + 1 < table_.size(); ++row) {
    table[row].a_step = table[row + 1].a - table[row].a;
    table[row].b_step = table[row + 1].b - table[row].b;
  }
}

void SweepPoser::set_pose(std::span<const glm::mat4> world_pose) {
  for (std::size_t j = 0; j < world_pose.size(); ++j) {
    joint_rotation_[j] = rotation_of(world_pose[j]) * rest_rotation_inverse_[j];
    pose_joint_[j] = glm::vec3(world_pose[j][3]);
  }
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    pose_key_ellipses(bound_.sweeps[s], mitre_spread_[s], bound_.model.skeleton, joint_rotation_,
                      rest_joint_, pose_joint_, posed_keys_[s]);
    if (key_adjuster_) key_adjuster_(static_cast<int>(s), posed_keys_[s]);
    sweeps_[s].set_key_frames(posed_keys_[s]);
    sweeps_[s].set_key_half_axes(posed_keys_[s]);
  }
  refresh_table();
}

void SweepPoser::deform(std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
                        std::span<glm::vec3> normals, int threads) {
  run_in_vertex_blocks(vertex_kinds_->item_count(), threads,
                       [&](std::size_t begin, std::size_t end) {
                         vertex_kinds_->evaluate(table_, skinning, positions, begin, end);
                       });
  if (!normals.empty()) normals_.compute(positions, normals);
}

glm::vec3 SweepPoser::reference_position(std::size_t v, std::span<const glm::mat4> skinning) const {
  const VertexBinding& vb = bound_.vertices[v];
  glm::vec3 p = vb.skin_weight * skinned_position(bound_, skinning, v);
  for (int k = 0; k < kSweepsPerVertex; ++k)
    if (vb.sweep[k] >= 0)
      p += vb.weight[k] * evaluate_point(sweeps_[vb.sweep[k]], vb.coordinate[k]);
  return p;
}

}  // namespace sweepd::deform
