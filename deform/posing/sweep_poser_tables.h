// SweepPoserTables: what SweepPoser (sweep_poser.h) needs of a bound model that never changes
// after binding — the rest sweeps, the mitre spread of every joint key, the layout of the
// per-frame sample table (which span and weights each row reads), the vertices grouped by kind
// with their sample rows (SweepVertexKinds), the rest joint frames and the welded-normals
// topology. Built once per model (make_sweep_poser_tables) and shared read-only by every
// SweepPoser of that model, on any thread.
// Inputs:  bound         the BoundModel (must outlive the tables)
//          instructions  what the vertex loops run on
// Output:  the tables; rows = Σ over sweeps of kSamplesPerSpan × spans + 1.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/mesh/welded_normals.h"
#include "deform/posing/plane_turn_limit.h"
#include "deform/posing/sweep_vertex_kinds.h"
#include "deform/sweep/sweep.h"

namespace sweepd::deform {

struct SweepPoserTables {
  static constexpr int kSamplesPerSpan = 64;
  struct SampleRun {  // consecutive table rows that read the same span of one sweep
    std::uint32_t begin, end;
    std::uint16_t sweep, span;
  };
  struct SampleAxisWeights {  // a = Σ axis[r] α_{first + r} (b likewise with β)
    std::uint32_t first;
    float axis[3];
  };

  const BoundModel* bound = nullptr;
  std::vector<Sweep> rest_sweeps;                               // per sweep
  std::vector<std::vector<std::array<float, 3>>> mitre_spread;  // per sweep (key_posing.h)
  // How each table row follows from its sweep's data. Per row: C = Σ spline[r] · (P_span,
  // P_span+1, P''_2span, P''_2span+1), Q = nlerp(q_span, q_span+1, q_mix); a, b and the offset o
  // (the ellipse's centre is C + R (o, 0)) from the axis weights.
  std::vector<SampleRun> sample_runs;
  std::array<std::vector<float>, 4> sample_spline;
  std::vector<float> sample_q_mix;
  std::vector<SampleAxisWeights> sample_axis;
  std::vector<std::uint32_t> first_row;           // per sweep: its first table row
  std::vector<std::vector<SpanRoom>> span_rooms;  // per sweep, per key span (plane_turn_limit.h)
  std::optional<SweepVertexKinds> vertex_kinds;
  std::vector<glm::mat4> world_rest;  // J
  std::vector<glm::quat> rest_rotation_inverse;
  std::vector<glm::vec3> rest_joint;
  std::optional<WeldedNormals> normals;
};

// The table row at or below parameter t of sweep `sweep` (the last row's predecessor at t = 1),
// and the fraction of the way to the next row.
struct SampleRowOf {
  std::uint32_t row;
  float fraction;
};
SampleRowOf sample_row_of(const SweepPoserTables& tables, int sweep, float t);

// The rotation of a world joint matrix, its columns normalised (scale removed).
glm::quat unit_rotation_of(const glm::mat4& world);
// The influences the skinned share follows: the binding's own, else the model's (#V each).
std::span<const std::array<std::uint16_t, kInfluences>> skinned_share_joints(
    const BoundModel& bound);
std::span<const std::array<float, kInfluences>> skinned_share_weights(const BoundModel& bound);

std::shared_ptr<const SweepPoserTables> make_sweep_poser_tables(
    const BoundModel& bound,
    VertexLoopInstructions instructions = widest_vertex_loop_instructions());

}  // namespace sweepd::deform
