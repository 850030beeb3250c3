// Rigid stays rigid (issue 47 item 4, deform/blending/rigid_islands.h): a segmented character's
// plates — separate pieces of mesh weighted 1.0 to one joint — move exactly as skinning moves
// them, however far the limb under them bends, while the body around them stays swept.
//
// The character: the shared male with three box plates floating 1 cm off the skin, at the front
// of the left knee (weighted to the shin's joint), over the left elbow (the forearm's) and on
// the left thigh (the thigh's). Posed at the range of motion's peaks (knee and elbow at 150°,
// knee to chest) and compared with LBS: every plate vertex where LBS puts it, within 1e-5 m
// (float rounding of the same skinning matrices); before rigid islands the sweep moved the
// plates by up to 1.1 cm from where skinning puts them (52 of the 96 plate vertices checked).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "deform/blending/rigid_islands.h"
#include "deform/mesh/welded_mesh.h"
#include "motion/own_skeleton_clip.h"
#include "motion/range_of_motion.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

// Appends an axis-aligned box of half size `half` at `centre`, weighted 1.0 to `joint`; returns
// its vertex ids.
std::vector<std::uint32_t> add_plate(Model& model, glm::vec3 centre, glm::vec3 half, int joint) {
  const auto first = static_cast<std::uint32_t>(model.positions.size());
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 sign(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1);
    model.positions.push_back(centre + sign * half);
    model.normals.push_back(glm::normalize(sign));
    if (model.has_uvs()) model.uvs.push_back({0.0f, 0.0f});
    model.skin_joints.push_back({static_cast<std::uint16_t>(joint), 0, 0, 0});
    model.skin_weights.push_back({1.0f, 0.0f, 0.0f, 0.0f});
  }
  // Six faces, two triangles each, wound outwards.
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces)
    for (const int k : {f[0], f[1], f[2], f[0], f[2], f[3]}) model.indices.push_back(first + k);
  std::vector<std::uint32_t> ids(8);
  for (int k = 0; k < 8; ++k) ids[k] = first + k;
  return ids;
}

class RigidIslands : public ::testing::Test {
 protected:
  void SetUp() override {
    const BoundModel* male = test::shared_male();
    if (!male) GTEST_SKIP() << "shared data absent (see ../shared/data/SOURCES.md)";
    model_ = male->model;
    model_.parts.clear();
    const RigMap& rig = male->rig;
    const std::vector<glm::mat4> world = model_.skeleton.world_rest_matrices();
    const BodyAxes axes = rest_body_axes(rig, world);
    auto at = [&](int joint) { return glm::vec3(world[joint][3]); };
    // Off the skin in front: the limb's rest section reaches ~7 cm from its joints.
    const glm::vec3 front = 0.09f * axes.forward;
    plates_.push_back(add_plate(model_, at(rig.left_leg.lower) + front, glm::vec3(0.04f),
                                rig.left_leg.lower));
    plates_.push_back(add_plate(model_, at(rig.left_arm.lower) - 0.07f * axes.forward,
                                glm::vec3(0.03f), rig.left_arm.lower));
    plates_.push_back(add_plate(model_,
                                0.5f * (at(rig.left_leg.upper) + at(rig.left_leg.lower)) + front,
                                glm::vec3(0.05f, 0.08f, 0.02f), rig.left_leg.upper));
    ASSERT_EQ(model_.validate(), "");
    bound_ = std::make_unique<BoundModel>(bind(model_, rig));
  }

  Model model_;
  std::vector<std::vector<std::uint32_t>> plates_;
  std::unique_ptr<BoundModel> bound_;
};

TEST_F(RigidIslands, ArePlatesOnlyAndAreLeftToSkinning) {
  const std::vector<int> joint_of =
      rigid_island_joints(model_, weld_mesh(model_.positions, model_.indices));
  const std::size_t plate_vertices = 8 * plates_.size();
  EXPECT_EQ(std::count_if(joint_of.begin(), joint_of.end(), [](int j) { return j >= 0; }),
            static_cast<long>(plate_vertices))
      << "the male's own pieces are blended, not rigid";
  for (const auto& plate : plates_)
    for (const std::uint32_t v : plate) EXPECT_EQ(bound_->vertices[v].skin_weight, 1.0f);
  // The body stays swept: as many vertices with a sweep share as the male alone has.
  const BoundModel* male = test::shared_male();
  auto swept = [](const BoundModel& bound, std::size_t n) {
    return std::count_if(bound.vertices.begin(), bound.vertices.begin() + n,
                         [](const VertexBinding& b) { return b.skin_weight < 1.0f; });
  };
  const std::size_t body = male->model.vertex_count();
  EXPECT_NEAR(static_cast<double>(swept(*bound_, body)), static_cast<double>(swept(*male, body)),
              0.001 * body);
}

TEST_F(RigidIslands, PlatesMoveAsSkinningMovesThemAtTheRangeOfMotionsPeaks) {
  const motion::RangeOfMotion rom = motion::range_of_motion(model_.skeleton, bound_->rig);
  const motion::OwnSkeletonClip player(rom.clip, model_.skeleton);
  test::Posing posing(*bound_);
  for (const motion::RomMove& move : rom.moves) {
    if (move.name != "knee flexion 150°" && move.name != "elbow flexion 150°" &&
        move.name != "left knee to chest" && move.name != "deep squat")
      continue;
    SCOPED_TRACE(move.name);
    const Pose pose = player.pose_at_frame(move.peak_frame);
    const std::vector<glm::vec3> sweep = test::deformed(posing, pose, DeformMethod::kSweep);
    const std::vector<glm::vec3> lbs = test::deformed(posing, pose, DeformMethod::kLbs);
    for (const auto& plate : plates_)
      for (const std::uint32_t v : plate)
        EXPECT_LT(glm::distance(sweep[v], lbs[v]), 1e-5f) << "plate vertex " << v;
  }
}

}  // namespace
}  // namespace sweepd::deform
