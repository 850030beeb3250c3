#include "deform/posing/plane_turn_limit.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/quaternion.hpp>

namespace sweepd::deform {

namespace {

constexpr float kTwoPi = 6.28318530718f;
constexpr float kHalfTurn = 0.5f * kTwoPi;

// The swing between two unit normals as a rotation vector (angle about their common normal).
glm::vec3 swing_between(const glm::vec3& from, const glm::vec3& to) {
  const glm::vec3 axis = glm::cross(from, to);
  const float sine = glm::length(axis);
  if (!(sine > 1e-9f)) return glm::vec3(0.0f);
  return axis * (std::atan2(sine, glm::dot(from, to)) / sine);
}

// A span's turn at rest, with room for the float rounding of posing the rest keys again (1e-6
// rad), which must not count as a turn.
float turn_at_rest(const SpanRoom& room) { return room.rest_turn * 1.001f + 1e-4f; }

// A span's limit for a turn about `axis` (unit): (1 - kLeastSpeedShare) s / reach towards the
// bend's inside, never below its turn at rest.
float span_limit(std::span<const SweepSample> rows, int samples_per_span, int span,
                 const SpanRoom& room, const glm::vec3& axis) {
  const SweepSample& from = rows[span * samples_per_span];
  const SweepSample& to = rows[(span + 1) * samples_per_span];
  const SweepSample& middle = rows[span * samples_per_span + samples_per_span / 2];
  const float at_rest = turn_at_rest(room);
  const glm::vec3 normal = glm::normalize(from.normal + to.normal);
  const float forward = glm::dot(normal, to.centre - from.centre);
  if (!(forward > 0.0f)) return at_rest;
  const glm::vec3 inside = glm::cross(axis, normal);  // where the plane's points slow down
  const float angle = std::atan2(glm::dot(inside, middle.y_axis), glm::dot(inside, middle.x_axis));
  const float position = (angle < 0.0f ? angle + kTwoPi : angle) / kTwoPi * kReachDirections;
  const int below = std::min(static_cast<int>(position), kReachDirections - 1);
  const float reach = std::max(room.reach[below], room.reach[(below + 1) % kReachDirections]);
  // No bound skin that way: any turn up to a half turn folds nothing.
  if (!(reach > 0.0f)) return kHalfTurn;
  return std::min(std::max((1.0f - kLeastSpeedShare) * forward / reach, at_rest), kHalfTurn);
}

}  // namespace

std::vector<SpanRoom> span_rooms(const BoundModel& bound, int sweep, const Sweep& rest) {
  const auto t = rest.parameters();
  const int spans = rest.key_count() - 1;
  std::vector<SpanRoom> rooms(spans);
  for (int i = 0; i < spans; ++i)
    rooms[i].rest_turn = glm::length(swing_between(rest.normal(static_cast<float>(t[i])),
                                                   rest.normal(static_cast<float>(t[i + 1]))));
  std::array<glm::vec2, kReachDirections> direction;
  for (int j = 0; j < kReachDirections; ++j) {
    const float angle = kTwoPi * static_cast<float>(j) / kReachDirections;
    direction[j] = {std::cos(angle), std::sin(angle)};
  }
  for (const VertexBinding& vb : bound.vertices)
    for (int k = 0; k < kSweepsPerVertex; ++k) {
      if (vb.sweep[k] != sweep || vb.weight[k] < kReachLeastWeight) continue;
      const SweepCoordinate& c = vb.coordinate[k];
      const int span = std::clamp(
          static_cast<int>(std::upper_bound(t.begin() + 1, t.end() - 1, static_cast<double>(c.t)) -
                           t.begin()) -
              1,
          0, spans - 1);
      // Its place in the plane, from the ellipse's centre (which the offset o(t) moves).
      const glm::vec2 local((rest.a(c.t) + c.da) * std::cos(c.theta),
                            (rest.b(c.t) + c.db) * std::sin(c.theta));
      for (int j = 0; j < kReachDirections; ++j)
        rooms[span].reach[j] = std::max(rooms[span].reach[j], glm::dot(local, direction[j]));
    }
  return rooms;
}

namespace {

// The rotation by the rotation vector `turn` (angle |turn| about its direction), as a unit
// quaternion.
glm::quat quaternion_of(const glm::vec3& turn) {
  const float angle = glm::length(turn);
  if (!(angle > 0.0f)) return glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  return glm::angleAxis(angle, turn / angle);
}

}  // namespace

bool limit_plane_turns(std::span<SweepSample> rows, int samples_per_span,
                       std::span<const SpanRoom> rooms, std::span<glm::quat> corrections,
                       PlaneTurnScratch& scratch) {
  const int spans = static_cast<int>(rooms.size());
  if (spans < 2) return false;  // one span: no neighbour to take its excess
  scratch.turn.resize(spans);
  scratch.limited.resize(spans);
  scratch.room.resize(spans);
  glm::vec3 total(0.0f);
  for (int i = 0; i < spans; ++i) {
    scratch.turn[i] =
        swing_between(rows[i * samples_per_span].normal, rows[(i + 1) * samples_per_span].normal);
    total += scratch.turn[i];
  }
  // Each span's limit about its own turn's axis (about the sweep's whole turn where it hardly
  // turns itself), fixed for this frame: a few operations per span.
  const float total_angle = glm::length(total);
  bool over = false;
  float room_sum = 0.0f;
  for (int i = 0; i < spans; ++i) {
    const float angle = glm::length(scratch.turn[i]);
    const glm::vec3 axis = angle > 1e-4f         ? scratch.turn[i] / angle
                           : total_angle > 1e-6f ? total / total_angle
                                                 : glm::vec3(0.0f);
    scratch.room[i] =
        axis == glm::vec3(0.0f) ? kHalfTurn : span_limit(rows, samples_per_span, i, rooms[i], axis);
    room_sum += scratch.room[i];
    over = over || angle > scratch.room[i];
    scratch.limited[i] = scratch.turn[i];
  }
  if (!over) return false;
  // Each span over its limit hands the excess to its neighbours, half each (all to the one
  // neighbour at the sweep's ends), until none is over.
  bool within = false;
  for (int round = 0; round < 8 * spans && !within && room_sum >= total_angle; ++round) {
    within = true;
    for (int i = 0; i < spans; ++i) {
      glm::vec3& limited = scratch.limited[i];
      const float angle = glm::length(limited);
      const float excess = angle - scratch.room[i];
      if (!(excess > 1e-5f)) continue;
      const glm::vec3 handed = excess / angle * limited;
      limited -= handed;
      if (i == 0) {
        scratch.limited[1] += handed;
      } else if (i == spans - 1) {
        scratch.limited[i - 1] += handed;
      } else {
        scratch.limited[i - 1] += 0.5f * handed;
        scratch.limited[i + 1] += 0.5f * handed;
      }
      within = false;
    }
  }
  if (!within) {
    // The sweep as a whole has too little room for the bend: the whole turn is shared in
    // proportion to the limits, so every span takes the same share of its limit and none folds
    // further than another.
    for (int i = 0; i < spans; ++i) scratch.limited[i] = total * (scratch.room[i] / room_sum);
  }
  // The correction at each key (the difference of the turns summed from the first key), as a
  // quaternion; each row's is the normalised blend of its span's two, linear in the row.
  glm::vec3 at_key(0.0f);
  glm::quat from = quaternion_of(at_key);
  for (int i = 0; i < spans; ++i) {
    at_key += scratch.limited[i] - scratch.turn[i];
    glm::quat to = quaternion_of(at_key);
    if (glm::dot(from, to) < 0.0f) to = -to;
    const int last = i + 1 == spans ? samples_per_span : samples_per_span - 1;
    for (int r = 0; r <= last; ++r) {
      const float mix = static_cast<float>(r) / samples_per_span;
      const glm::quat turn = r == 0 ? from : glm::normalize((1.0f - mix) * from + mix * to);
      SweepSample& row = rows[i * samples_per_span + r];
      corrections[i * samples_per_span + r] = turn;
      const glm::mat3 rotation = glm::mat3_cast(turn);
      row.x_axis = rotation * row.x_axis;
      row.y_axis = rotation * row.y_axis;
      row.normal = rotation * row.normal;
    }
    from = to;
  }
  return true;
}

}  // namespace sweepd::deform
