// The plane turn limit (deform/posing/plane_turn_limit.h): on a hand-made sweep with one sharp
// span, every span ends within its limit, the end planes and the total turn stay; a gentle sweep
// is left bit for bit; and on the shared male with the spine bent 45° forward (where the belly's
// planes cross) the fast path still matches the direct evaluation, on every instruction set and
// thread count.
#include "deform/posing/plane_turn_limit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "deform/model/forward_kinematics.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

constexpr int kRows = SweepPoserTables::kSamplesPerSpan;
constexpr float kReach = 0.15f;  // every span's skin reaches 15 cm every way

// Keys up the y axis 10 cm apart except one 3 cm span (the third) that turns `sharp` radians
// about x; the table rows of the sweep through them, as SweepPoser fills them.
std::vector<SweepSample> rows_of_a_bend(float sharp) {
  const float heights[] = {0.0f, 0.1f, 0.2f, 0.23f, 0.33f, 0.43f};
  std::vector<KeyEllipse> keys;
  for (int k = 0; k < 6; ++k) {
    KeyEllipse key;
    const float angle = k >= 3 ? sharp : 0.0f;
    // The plane's normal starts along +y and turns about x.
    key.orientation =
        glm::angleAxis(angle, glm::vec3(1, 0, 0)) * glm::angleAxis(-1.5707963f, glm::vec3(1, 0, 0));
    key.centre = glm::vec3(0.0f, heights[k], 0.0f);
    if (k > 3)
      key.centre = glm::vec3(0.0f, 0.23f, 0.0f) +
                   (heights[k] - 0.23f) * (key.orientation * glm::vec3(0, 0, 1));
    key.a = key.b = 0.1f;
    keys.push_back(key);
  }
  const Sweep sweep(keys);
  const auto t = sweep.parameters();
  std::vector<SweepSample> rows;
  for (int i = 0; i < 5; ++i)
    for (int r = 0; r < kRows || (i == 4 && r == kRows); ++r) {
      const SweepFrame f = sweep.frame(static_cast<float>(t[i] + (t[i + 1] - t[i]) * r / kRows));
      rows.push_back({f.centre, f.a, f.rotation[0], f.b, f.rotation[1], 0.0f, f.rotation[2], 0.0f});
    }
  return rows;
}

std::vector<SpanRoom> even_rooms() {
  SpanRoom room;
  room.reach.fill(kReach);
  return std::vector<SpanRoom>(5, room);
}

float swing(const glm::vec3& a, const glm::vec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

TEST(PlaneTurnLimit, ASharpSpanHandsItsTurnToItsNeighboursAndTheEndsStay) {
  const float sharp = glm::radians(40.0f);
  std::vector<SweepSample> rows = rows_of_a_bend(sharp);
  const std::vector<SweepSample> posed = rows;
  std::vector<glm::quat> corrections(rows.size());
  PlaneTurnScratch scratch;
  ASSERT_TRUE(limit_plane_turns(rows, kRows, even_rooms(), corrections, scratch));
  float total = 0.0f;
  for (int i = 0; i < 5; ++i) {
    const SweepSample& from = rows[i * kRows];
    const SweepSample& to = rows[(i + 1) * kRows];
    const float turn = swing(from.normal, to.normal);
    const float forward =
        glm::dot(glm::normalize(from.normal + to.normal), to.centre - from.centre);
    const float limit = (1.0f - kLeastSpeedShare) * forward / kReach;
    std::printf("span %d: turns %.1f deg, limit %.1f deg (before %.1f)\n", i, glm::degrees(turn),
                glm::degrees(limit),
                glm::degrees(swing(posed[i * kRows].normal, posed[(i + 1) * kRows].normal)));
    // Within 2 % of the limit: the limits were taken from the posed rows' normals, which the
    // turn then tilts by a few degrees (cos 10° = 0.985 on the forward distance).
    EXPECT_LE(turn, 1.02f * limit) << "span " << i;
    total += turn;
    // The centres stay: only the frames turn.
    EXPECT_EQ(rows[i * kRows].centre, posed[i * kRows].centre);
  }
  // The bend is in one plane, so the spans' turns add up to the 40° between the ends.
  EXPECT_NEAR(glm::degrees(total), 40.0f, 0.05f);
  // The first row is not turned; the last by the float rounding of the sum (1e-6 rad).
  EXPECT_EQ(rows.front().normal, posed.front().normal);
  EXPECT_NEAR(glm::length(rows.back().normal - posed.back().normal), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(rows.back().x_axis - posed.back().x_axis), 0.0f, 1e-5f);
  // Each row's frame stays a rotation: unit, orthogonal columns.
  for (const SweepSample& row : rows) {
    EXPECT_NEAR(glm::length(row.x_axis), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(row.x_axis, row.normal), 0.0f, 1e-5f);
  }
}

TEST(PlaneTurnLimit, ASweepWithinItsLimitsIsLeftAsPosed) {
  std::vector<SweepSample> rows = rows_of_a_bend(glm::radians(9.0f));  // limit 9.2° on 3 cm
  const std::vector<SweepSample> posed = rows;
  std::vector<glm::quat> corrections(rows.size());
  PlaneTurnScratch scratch;
  EXPECT_FALSE(limit_plane_turns(rows, kRows, even_rooms(), corrections, scratch));
  EXPECT_EQ(0, std::memcmp(rows.data(), posed.data(), rows.size() * sizeof(SweepSample)));
}

// The shared male's spine bent 45° forward: the torso's planes cross inside the belly, so the
// limit turns its rows; the fast path then matches the direct evaluation (which turns its frames
// by the same rows' turns) within the 1e-5 of the height, on every instruction set, and
// threads are bit-identical.
TEST(PlaneTurnLimit, TheFastPathMatchesTheDirectEvaluationWhereTheLimitTurnsTheRows) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  const Pose pose = test::spine_bent_forward(male, 45.0f);
  std::vector<glm::mat4> world(model.skeleton.joints.size()), skinning(world.size());
  forward_kinematics(model.skeleton, pose, world);
  skinning_matrices(world, world_rest_inverse_matrices(model.skeleton), skinning);
  float lo = 1e9f, hi = -1e9f;
  for (const glm::vec3& p : model.positions) lo = std::min(lo, p.y), hi = std::max(hi, p.y);
  std::vector<VertexLoopInstructions> sets = {VertexLoopInstructions::kBaseline};
  if (widest_vertex_loop_instructions() != VertexLoopInstructions::kBaseline)
    sets.push_back(widest_vertex_loop_instructions());
  const std::size_t n = model.vertex_count();
  for (const VertexLoopInstructions set : sets) {
    SweepPoser poser(male, set);
    poser.set_pose(world);
    const int torso = test::sweep_of(male, BodyPart::kTorso);
    ASSERT_TRUE(poser.plane_turns_limited(torso)) << "the torso's planes crossed in the belly";
    std::vector<glm::vec3> one(n), three(n);
    poser.deform(skinning, one, {}, 1);
    poser.deform(skinning, three, {}, 3);
    EXPECT_EQ(0, std::memcmp(one.data(), three.data(), n * sizeof(glm::vec3)));
    float worst = 0.0f;
    for (std::size_t v = 0; v < n; ++v)
      worst = std::max(worst, glm::length(one[v] - poser.reference_position(v, skinning)));
    std::printf("instruction set %d: worst %.3g m from direct evaluation\n", static_cast<int>(set),
                worst);
    EXPECT_LE(worst, 1e-5f * (hi - lo));
  }
}

}  // namespace
}  // namespace sweepd::deform
