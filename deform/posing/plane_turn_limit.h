// Plane turn limit: keeps a posed sweep's ellipse planes from crossing inside the skin bound to
// them (issue 47's "torn belly"), in the per-frame sample table; the torso's sweep only
// (sweep_poser_tables.cpp says why).
//
// A point bound to a sweep moves forward with its plane at N · C̃' less the frame's turn rate
// times its distance from the ellipse's centre towards the inside of the bend: where a key span
// turns its plane by δ over a forward distance s of the ellipse's centre, its planes cross at
// s / δ from the centre, and the skin bound beyond that runs backwards through itself and its
// triangles flip (metrics/sweep_plane_crossing.h). On the heavy male over cmu_01_03 the five
// lowest torso spans turn 13-19° over 2-5 cm while the belly reaches 12-15 cm in front.
// So each key span may turn its plane (the swing of N between its two key rows; a twist about N
// crosses nothing) by at most (1 - kLeastSpeedShare) s / reach, reach being how far the skin
// bound to the span reaches, at rest, in the direction of the bend's inside (measured at
// binding in kReachDirections directions of the ellipse's plane). A span that turns further
// keeps its limit and hands the excess on to the spans beside it, half to each (all of it away
// from the sweep's ends, whose planes stay as posed so the sweeps that meet there still fit),
// until every span is within its limit. Where the whole sweep has too little room (the heavy
// male's torso sweep, pelvis to spine_03, is 18 cm of centre line that cmu_01_03 frame 1100
// bends 77° while its belly reaches 16-20 cm in front of it: room for 53°), the whole turn is
// shared in proportion to the limits, so every span keeps the same share of its room and none
// folds further than another; the planes then still cross, nearer the skin's edge. Each span's
// limit is taken once a frame, about its own turn's axis. The rows are then turned, about their
// ellipse centres, by the difference between the spread and the posed turn summed from the
// sweep's first key (a quaternion per key, blended linearly along the span's rows): centres,
// half-axes and the end rows stay, the section keeps its shape, and the bend is taken over more
// of the sweep instead of folding at one span. A span's limit is never below its turn at rest,
// so the rest pose (and any pose within every limit, most of them) is left exactly as posed.
// Cost per frame: a few operations per key span; the rows of a sweep are turned (a quaternion
// blend and a rotation each) only when one of its spans is over its limit.
#pragma once

#include <array>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/posing/sweep_vertex_kinds.h"
#include "deform/sweep/sweep.h"

namespace sweepd::deform {

inline constexpr int kReachDirections = 16;
// The share of the centre's forward speed that the innermost bound point keeps at a span's
// limit: the skin there is compressed to at most this much, never turned inside out.
inline constexpr float kLeastSpeedShare = 0.2f;
// A point counts towards its span's reach where it follows the sweep with at least this weight
// (a point mostly moved by another sweep or by skinning does not fold with this one).
inline constexpr float kReachLeastWeight = 0.25f;

// One key span of one sweep, fixed at binding.
struct SpanRoom {
  // The farthest bound point from the ellipse's centre along direction j (angle 2πj /
  // kReachDirections from the ellipse's x axis), 0 where none lies that way.
  std::array<float, kReachDirections> reach{};
  float rest_turn = 0.0f;  // the swing of its plane between its keys at rest, radians
};

// The rooms of sweep `sweep` of `bound` (its rest sweep `rest`): key_count() - 1 spans.
std::vector<SpanRoom> span_rooms(const BoundModel& bound, int sweep, const Sweep& rest);

struct PlaneTurnScratch {
  std::vector<glm::vec3> turn, limited;
  std::vector<float> room;
};

// rows: one sweep's table rows, spans × samples_per_span + 1 (the keys every samples_per_span
// rows); rooms: its spans. Turns the rows and writes each row's turn (a unit quaternion, world)
// into corrections (rows.size()) where any span is over its limit, and returns whether it did
// (rows and corrections are left alone where it did not).
bool limit_plane_turns(std::span<SweepSample> rows, int samples_per_span,
                       std::span<const SpanRoom> rooms, std::span<glm::quat> corrections,
                       PlaneTurnScratch& scratch);

}  // namespace sweepd::deform
