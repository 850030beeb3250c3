#include "deform/posing/sweep_poser_tables.h"

#include <algorithm>
#include <cmath>

#include "deform/binding/rest_sweep.h"
#include "deform/binding/sweep_coordinates.h"
#include "deform/posing/key_posing.h"

namespace sweepd::deform {

glm::quat unit_rotation_of(const glm::mat4& m) {
  return glm::normalize(
      glm::quat_cast(glm::mat3(glm::normalize(glm::vec3(m[0])), glm::normalize(glm::vec3(m[1])),
                               glm::normalize(glm::vec3(m[2])))));
}

std::span<const std::array<std::uint16_t, kInfluences>> skinned_share_joints(
    const BoundModel& bound) {
  return bound.skinned_share_joints.empty() ? bound.model.skin_joints : bound.skinned_share_joints;
}

std::span<const std::array<float, kInfluences>> skinned_share_weights(const BoundModel& bound) {
  return bound.skinned_share_weights.empty() ? bound.model.skin_weights
                                             : bound.skinned_share_weights;
}

SampleRowOf sample_row_of(const SweepPoserTables& tables, int sweep, float t_of_point) {
  constexpr int kSamplesPerSpan = SweepPoserTables::kSamplesPerSpan;
  const auto t = tables.rest_sweeps[sweep].parameters();
  const std::size_t span = std::min<std::size_t>(
      std::upper_bound(t.begin() + 1, t.end() - 1, static_cast<double>(t_of_point)) - t.begin() - 1,
      t.size() - 2);
  const double within = (t_of_point - t[span]) / (t[span + 1] - t[span]) * kSamplesPerSpan;
  const int step = std::clamp(static_cast<int>(within), 0, kSamplesPerSpan - 1);
  return {tables.first_row[sweep] + static_cast<std::uint32_t>(span * kSamplesPerSpan + step),
          static_cast<float>(within - step)};
}

std::shared_ptr<const SweepPoserTables> make_sweep_poser_tables(
    const BoundModel& bound, VertexLoopInstructions instructions) {
  constexpr int kSamplesPerSpan = SweepPoserTables::kSamplesPerSpan;
  auto tables = std::make_shared<SweepPoserTables>();
  SweepPoserTables& out = *tables;
  out.bound = &bound;
  out.normals.emplace(bound.model.positions, bound.model.indices);
  const Skeleton& skeleton = bound.model.skeleton;
  out.world_rest = skeleton.world_rest_matrices();
  for (const glm::mat4& m : out.world_rest) {
    out.rest_rotation_inverse.push_back(glm::inverse(unit_rotation_of(m)));
    out.rest_joint.emplace_back(m[3]);
  }
  // Table rows: kSamplesPerSpan per key span, aligned with the keys, plus the last key.
  for (const BoundSweep& sweep : bound.sweeps) {
    out.rest_sweeps.push_back(rest_sweep(sweep, bound.options));
    out.mitre_spread.push_back(mitre_spread(sweep));
    // The torso's spans only: on the arms the turned rows parted the mesh from the swept-volume
    // integral that volume correction holds (the male's arm region at a 100-150° elbow 0.025-0.18
    // of its volume from the integral, 0.02 allowed), which integrates the sweep's own frames.
    out.span_rooms.push_back(sweep.part == BodyPart::kTorso
                                 ? span_rooms(bound, static_cast<int>(out.rest_sweeps.size()) - 1,
                                              out.rest_sweeps.back())
                                 : std::vector<SpanRoom>{});
    out.first_row.push_back(static_cast<std::uint32_t>(out.sample_q_mix.size()));
    const Sweep& curve = out.rest_sweeps.back();
    const auto t = curve.parameters();
    for (std::size_t i = 0; i + 1 < t.size(); ++i)
      for (int k = 0; k <= kSamplesPerSpan; ++k) {
        if (k == kSamplesPerSpan && i + 2 < t.size()) break;  // the next span's first row
        const double at = t[i] + (t[i + 1] - t[i]) * k / kSamplesPerSpan;
        const auto spline = curve.centre_curve().weights(at);
        const auto row = static_cast<std::uint32_t>(out.sample_q_mix.size());
        const auto sweep_index = static_cast<std::uint16_t>(out.rest_sweeps.size() - 1);
        const auto span = static_cast<std::uint16_t>(spline.span);
        if (out.sample_runs.empty() || out.sample_runs.back().sweep != sweep_index ||
            out.sample_runs.back().span != span)
          out.sample_runs.push_back({row, row, sweep_index, span});
        ++out.sample_runs.back().end;
        for (int r = 0; r < 4; ++r) out.sample_spline[r].push_back(static_cast<float>(spline.w[r]));
        out.sample_q_mix.push_back(
            static_cast<float>((at - t[spline.span]) / (t[spline.span + 1] - t[spline.span])));
        std::array<double, InterpolatingQuadraticSpline::kMaxDegree + 1> basis{};
        SweepPoserTables::SampleAxisWeights axis{};
        axis.first = static_cast<std::uint32_t>(curve.a_function().nonzero_basis(at, basis));
        for (int r = 0; r < 3; ++r)
          axis.axis[r] = r <= curve.a_function().degree() ? static_cast<float>(basis[r]) : 0.0f;
        out.sample_axis.push_back(axis);
      }
  }

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
      const SampleRowOf at = sample_row_of(out, vb.sweep[k], c.t);
      SweepTerm term{};
      term.row = at.row;
      term.fraction = at.fraction;
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
  out.vertex_kinds.emplace(bound.model, skinned_share_joints(bound), skinned_share_weights(bound),
                           skin_share, first_term, terms, instructions);

  return tables;
}

}  // namespace sweepd::deform
