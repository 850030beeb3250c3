#include "deform/posing/plane_turn_limit.h"

#include <algorithm>
#include <cmath>

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

glm::mat3 rotation_by(const glm::vec3& turn) {
  const float angle = glm::length(turn);
  if (!(angle > 0.0f)) return glm::mat3(1.0f);
  const glm::vec3 k = turn / angle;
  const float c = std::cos(angle), s = std::sin(angle);
  // Rodrigues: c I + s [k]x + (1 - c) k k^T, by columns.
  const glm::mat3 cross_k(glm::vec3(0.0f, k.z, -k.y), glm::vec3(-k.z, 0.0f, k.x),
                          glm::vec3(k.y, -k.x, 0.0f));
  return c * glm::mat3(1.0f) + s * cross_k + (1.0f - c) * glm::outerProduct(k, k);
}

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

bool limit_plane_turns(std::span<SweepSample> rows, int samples_per_span,
                       std::span<const SpanRoom> rooms, std::span<glm::vec3> corrections,
                       PlaneTurnScratch& scratch) {
  const int spans = static_cast<int>(rooms.size());
  if (spans < 2) return false;  // one span: no neighbour to take its excess
  scratch.turn.resize(spans);
  scratch.limited.resize(spans);
  bool over = false;
  for (int i = 0; i < spans; ++i) {
    const glm::vec3 turn =
        swing_between(rows[i * samples_per_span].normal, rows[(i + 1) * samples_per_span].normal);
    scratch.turn[i] = scratch.limited[i] = turn;
    const float angle = glm::length(turn);
    over = over || (angle > turn_at_rest(rooms[i]) &&
                    angle > span_limit(rows, samples_per_span, i, rooms[i], turn / angle));
  }
  if (!over) return false;
  // Each span over its limit hands the excess to its neighbours, half each (all to the one
  // neighbour at the sweep's ends), until none is over; a bend too sharp for the whole sweep
  // stops after a bounded number of rounds, spread as far as it got.
  bool within = false;
  for (int round = 0; round < 8 * spans && !within; ++round) {
    bool moved = false;
    for (int i = 0; i < spans; ++i) {
      glm::vec3& limited = scratch.limited[i];
      const float angle = glm::length(limited);
      if (!(angle > 1e-6f)) continue;
      const glm::vec3 axis = limited / angle;
      const float excess = angle - span_limit(rows, samples_per_span, i, rooms[i], axis);
      if (!(excess > 1e-5f)) continue;
      limited -= excess * axis;
      if (i == 0) {
        scratch.limited[1] += excess * axis;
      } else if (i == spans - 1) {
        scratch.limited[i - 1] += excess * axis;
      } else {
        scratch.limited[i - 1] += 0.5f * excess * axis;
        scratch.limited[i + 1] += 0.5f * excess * axis;
      }
      moved = true;
    }
    within = !moved;
  }
  if (!within) {
    // The sweep as a whole has too little room for the bend: every span takes the same share of
    // its limit (the whole turn shared in proportion to the limits about its axis), so no span
    // folds further than another.
    glm::vec3 total(0.0f);
    for (const glm::vec3& turn : scratch.turn) total += turn;
    const float angle = glm::length(total);
    if (angle > 1e-6f) {
      scratch.room.resize(spans);
      float sum = 0.0f;
      for (int i = 0; i < spans; ++i)
        sum += scratch.room[i] = span_limit(rows, samples_per_span, i, rooms[i], total / angle);
      for (int i = 0; i < spans; ++i) scratch.limited[i] = total * (scratch.room[i] / sum);
    }
  }
  glm::vec3 at_key(0.0f);  // the correction at span i's first key
  for (int i = 0; i < spans; ++i) {
    const glm::vec3 next = at_key + (scratch.limited[i] - scratch.turn[i]);
    const int last = i + 1 == spans ? samples_per_span : samples_per_span - 1;
    for (int r = 0; r <= last; ++r) {
      const float mix = static_cast<float>(r) / samples_per_span;
      const glm::vec3 turn = at_key + mix * (next - at_key);
      SweepSample& row = rows[i * samples_per_span + r];
      corrections[i * samples_per_span + r] = turn;
      const glm::mat3 rotation = rotation_by(turn);
      row.x_axis = rotation * row.x_axis;
      row.y_axis = rotation * row.y_axis;
      row.normal = rotation * row.normal;
    }
    at_key = next;
  }
  return true;
}

}  // namespace sweepd::deform
