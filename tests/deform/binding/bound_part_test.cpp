// bound_part (deform/binding/bound_part.h): some vertices of a binding posed alone land where
// they land when the whole body is posed, so the self-check may pose only what it changed.
#include "deform/binding/bound_part.h"

#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include "deform/binding/bind.h"
#include "deform/model/forward_kinematics.h"
#include "deform/model/pose.h"
#include "deform/posing/sweep_poser.h"
#include "mannequin/mannequin.h"

namespace sweepd::deform {
namespace {

TEST(BoundPart, ItsVerticesPoseAsTheyDoInTheWholeBody) {
  const Model model = mannequin::make_mannequin({.target_vertices = 6000});
  const RigMap rig = detect_rig_map(model.skeleton);
  const BoundModel bound = bind(model, rig);
  // A bent left elbow and knee: their sweeps' vertices move off their rest places.
  Pose pose = rest_pose(model.skeleton);
  for (const int joint : {rig.left_arm.lower, rig.left_leg.lower})
    pose.local_rotations[joint] =
        pose.local_rotations[joint] * glm::angleAxis(1.2f, glm::vec3(1, 0, 0));
  std::vector<glm::mat4> world(model.skeleton.size()), skinning(model.skeleton.size());
  forward_kinematics(model.skeleton, pose, world);
  skinning_matrices(world, world_rest_inverse_matrices(model.skeleton), skinning);

  std::vector<glm::vec3> whole(model.vertex_count());
  SweepPoser whole_poser(bound);
  whole_poser.set_pose(world);
  whole_poser.deform(skinning, whole, {});

  // Every third vertex in descending order, and a few (every 97th: as few as the self-check's
  // probe poses): any subset, any order.
  for (const std::uint32_t step : {3u, 97u}) {
    SCOPED_TRACE(step);
    std::vector<std::uint32_t> vertices;
    for (std::uint32_t v = model.vertex_count(); v-- > 0;)
      if (v % step == 0) vertices.push_back(v);
    const BoundModel part = bound_part(bound, vertices);
    ASSERT_EQ(part.model.vertex_count(), vertices.size());
    ASSERT_EQ(part.vertices.size(), vertices.size());
    EXPECT_TRUE(part.model.indices.empty());
    std::vector<glm::vec3> alone(vertices.size());
    SweepPoser part_poser(part);
    part_poser.set_pose(world);
    part_poser.deform(skinning, alone, {});
    int moved = 0;
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      // Bit for bit: each vertex by the same arithmetic, however the vertex loops group them.
      // The self-check's probe relies on it: its vertices, posed alone, must measure what
      // they measure posed with the rest of the sweep's.
      EXPECT_EQ(alone[i].x, whole[vertices[i]].x) << vertices[i];
      EXPECT_EQ(alone[i].y, whole[vertices[i]].y) << vertices[i];
      EXPECT_EQ(alone[i].z, whole[vertices[i]].z) << vertices[i];
      moved += glm::distance(whole[vertices[i]], model.positions[vertices[i]]) > 0.01f;
    }
    EXPECT_GT(moved, static_cast<int>(vertices.size()) / 20)
        << "the pose moves the sweeps' vertices, so the comparison means something";
  }
}

}  // namespace
}  // namespace sweepd::deform
