#include "deform/posing/sweep_poser.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "deform/binding/sweep_coordinates.h"
#include "deform/posing/key_posing.h"
#include "deform/simd/float_lanes.h"
#include "deform/simd/vertex_blocks.h"

namespace sweepd::deform {

namespace {

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

// A row's R(q / |q|) as three columns, from q without normalising it: 2 / |q|² scales the
// products.
inline void set_row_frame(const glm::quat& q, SweepSample& out) {
  const float x = q.x, y = q.y, z = q.z, w = q.w;
  const float scale = 2.0f / (x * x + y * y + z * z + w * w);
  const float xx = scale * x * x, yy = scale * y * y, zz = scale * z * z;
  const float xy = scale * x * y, xz = scale * x * z, yz = scale * y * z;
  const float wx = scale * w * x, wy = scale * w * y, wz = scale * w * z;
  out.x_axis = glm::vec3(1.0f - (yy + zz), xy + wz, xz - wy);
  out.y_axis = glm::vec3(xy - wz, 1.0f - (xx + zz), yz + wx);
  out.normal = glm::vec3(xz + wy, yz - wx, 1.0f - (xx + yy));
}

}  // namespace

SweepPoser::SweepPoser(const BoundModel& bound, VertexLoopInstructions instructions)
    : SweepPoser(make_sweep_poser_tables(bound, instructions)) {}

SweepPoser::SweepPoser(std::shared_ptr<const SweepPoserTables> tables)
    : tables_(std::move(tables)),
      bound_(*tables_->bound),
      sweeps_(tables_->rest_sweeps),
      sweep_data_(sweeps_.size()),
      table_(tables_->sample_q_mix.size()),
      row_turn_(table_.size()),
      sweep_turned_(sweeps_.size(), 0),
      joint_rotation_(tables_->world_rest.size()),
      pose_joint_(tables_->rest_joint),
      term_lanes_(tables_->vertex_kinds->term_lane_count()) {
  for (const BoundSweep& sweep : bound_.sweeps) posed_keys_.push_back(sweep.rest_keys);
  set_pose(tables_->world_rest);
}

void SweepPoser::refresh_table() {
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    SweepData& d = sweep_data_[s];
    const Sweep& sweep = sweeps_[s];
    const auto& curve = sweep.centre_curve();
    d.points.assign(curve.points().begin(), curve.points().end());
    d.second.assign(curve.span_second_derivatives().begin(), curve.span_second_derivatives().end());
    d.keys.assign(sweep.orientation_curve().keys().begin(), sweep.orientation_curve().keys().end());
    const auto alpha = sweep.alpha(), beta = sweep.beta();
    const auto offset_x = sweep.offset_x_function().controls();
    const auto offset_y = sweep.offset_y_function().controls();
    d.axis_controls.assign(alpha.size() + 2, glm::vec4(0.0f));
    for (std::size_t k = 0; k < alpha.size(); ++k)
      d.axis_controls[k] = glm::vec4(alpha[k], beta[k], offset_x[k], offset_y[k]);
  }
  // Centre and frame: one loop per run of rows on the same span, over the rows' weights only
  // (the span's points and keys are loop constants), so it vectorises.
  SweepSample* table = table_.data();
  const float* w0 = tables_->sample_spline[0].data();
  const float* w1 = tables_->sample_spline[1].data();
  const float* w2 = tables_->sample_spline[2].data();
  const float* w3 = tables_->sample_spline[3].data();
  const float* q_mix = tables_->sample_q_mix.data();
  for (const SweepPoserTables::SampleRun& run : tables_->sample_runs) {
    const SweepData& d = sweep_data_[run.sweep];
    const int i = run.span;
    const glm::vec3 p0 = d.points[i], p1 = d.points[i + 1];
    const glm::vec3 s0 = d.second[2 * i], s1 = d.second[2 * i + 1];
    for (std::uint32_t row = run.begin; row < run.end; ++row)
      table[row].centre = w0[row] * p0 + w1[row] * p1 + w2[row] * s0 + w3[row] * s1;
    const OrientationCurve& orientation = sweeps_[run.sweep].orientation_curve();
    if (orientation.kind() == OrientationCurveKind::kSmooth) {
      // The C2 curve is evaluated at each row (a few exponentials; not vectorised).
      const auto t = sweeps_[run.sweep].parameters();
      for (std::uint32_t row = run.begin; row < run.end; ++row)
        set_row_frame(glm::quat(orientation.unit(t[i] + q_mix[row] * (t[i + 1] - t[i]))),
                      table[row]);
      continue;
    }
    const glm::quat q0 = d.keys[i], q1 = d.keys[i + 1];
    for (std::uint32_t row = run.begin; row < run.end; ++row) {
      const float m = q_mix[row];
      set_row_frame((1.0f - m) * q0 + m * q1, table[row]);
    }
  }
  for (const SweepPoserTables::SampleRun& run : tables_->sample_runs) {
    const SweepData& d = sweep_data_[run.sweep];
    const float* controls = &d.axis_controls[0].x;
    for (std::uint32_t row = run.begin; row < run.end; ++row) {
      const SweepPoserTables::SampleAxisWeights& w = tables_->sample_axis[row];
      const float* k = controls + 4 * w.first;
      // a, b and the offset o at once: lanes (α, β, o_x, o_y).
      const FloatLanes axis =
          load_lanes(k) * w.axis[0] + load_lanes(k + 4) * w.axis[1] + load_lanes(k + 8) * w.axis[2];
      table[row].a = axis[0];
      table[row].b = axis[1];
      // The ellipse's centre C + R (o, 0) (KeyEllipse::offset).
      table[row].centre += axis[2] * table[row].x_axis + axis[3] * table[row].y_axis;
    }
  }
  // A sweep's last row gets the next sweep's first row: no term starts there.
  for (std::size_t row = 0; row + 1 < table_.size(); ++row) {
    table[row].a_step = table[row + 1].a - table[row].a;
    table[row].b_step = table[row + 1].b - table[row].b;
  }
  constexpr int kSamplesPerSpan = SweepPoserTables::kSamplesPerSpan;
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    const std::span<const SpanRoom> rooms = tables_->span_rooms[s];
    const std::size_t rows = rooms.size() * kSamplesPerSpan + 1;
    sweep_turned_[s] = limit_plane_turns(
        std::span(table_).subspan(tables_->first_row[s], rows), kSamplesPerSpan, rooms,
        std::span(row_turn_).subspan(tables_->first_row[s], rows), turn_scratch_);
  }
}

void SweepPoser::set_pose(std::span<const glm::mat4> world_pose) {
  for (std::size_t j = 0; j < world_pose.size(); ++j) {
    joint_rotation_[j] = unit_rotation_of(world_pose[j]) * tables_->rest_rotation_inverse[j];
    pose_joint_[j] = glm::vec3(world_pose[j][3]);
  }
  for (std::size_t s = 0; s < sweeps_.size(); ++s) {
    pose_key_ellipses(bound_.sweeps[s], tables_->mitre_spread[s], bound_.model.skeleton,
                      joint_rotation_, tables_->rest_joint, pose_joint_, posed_keys_[s]);
    if (key_adjuster_) key_adjuster_(static_cast<int>(s), posed_keys_[s]);
    sweeps_[s].set_key_frames(posed_keys_[s]);
    sweeps_[s].set_key_half_axes(posed_keys_[s]);
  }
  refresh_table();
}

void SweepPoser::deform(std::span<const glm::mat4> skinning, std::span<glm::vec3> positions,
                        std::span<glm::vec3> normals, int threads) {
  const SweepVertexKinds& kinds = *tables_->vertex_kinds;
  // Two passes (sweep_vertex_kinds.h): the second reads the term lanes the first wrote.
  run_in_vertex_blocks(
      kinds.batch_item_count(), threads,
      [&](std::size_t begin, std::size_t end) {
        kinds.evaluate_batches(table_, positions, term_lanes_, begin, end);
      },
      SweepVertexKinds::kItemGranule);
  run_in_vertex_blocks(kinds.junction_count(), threads, [&](std::size_t begin, std::size_t end) {
    kinds.evaluate_junctions(skinning, term_lanes_, positions, begin, end);
  });
  if (!normals.empty()) tables_->normals->compute(positions, normals, normal_sums_, threads);
}

glm::vec3 SweepPoser::reference_position(std::size_t v, std::span<const glm::mat4> skinning) const {
  const VertexBinding& vb = bound_.vertices[v];
  glm::vec3 p = vb.skin_weight * skinned_position(bound_, skinning, v);
  for (int k = 0; k < kSweepsPerVertex; ++k)
    if (vb.sweep[k] >= 0) p += vb.weight[k] * reference_point(vb.sweep[k], vb.coordinate[k]);
  return p;
}

glm::mat3 SweepPoser::row_turn_at(int s, float t) const {
  if (!sweep_turned_[s]) return glm::mat3(1.0f);
  const SampleRowOf at = sample_row_of(*tables_, s, t);
  const glm::quat below = row_turn_[at.row], above = row_turn_[at.row + 1];
  return glm::mat3_cast(glm::normalize((1.0f - at.fraction) * below + at.fraction * above));
}

glm::vec3 SweepPoser::reference_point(int s, const SweepCoordinate& c) const {
  const Sweep& sweep = sweeps_[s];
  if (!sweep_turned_[s]) return evaluate_point(sweep, c);
  const glm::vec3 local((sweep.a(c.t) + c.da) * std::cos(c.theta),
                        (sweep.b(c.t) + c.db) * std::sin(c.theta), c.c);
  return sweep.ellipse_centre(c.t) + row_turn_at(s, c.t) * (sweep.rotation(c.t) * local);
}

glm::vec3 SweepPoser::reference_normal(int s, float t) const {
  return row_turn_at(s, t) * sweeps_[s].normal(t);
}

}  // namespace sweepd::deform
