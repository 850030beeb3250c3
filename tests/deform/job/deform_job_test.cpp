// DeformJob's validation (deform/job/deform_job.h) on the shared male: each refused input names
// itself and its kind (joint count, pose, selection), the rotation length tolerance refuses
// rather than normalises, and run_validated guards only the sizes that protect memory.
#include "deform/job/deform_job.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

using Input = JobProblem::Input;

bool names(const JobProblem& problem, const std::string& text) {
  return problem.message.find(text) != std::string::npos;
}

TEST(DeformJob, AValidPoseHasNoProblemAndIsNormalisedInPlace) {
  REQUIRE_SHARED_MALE();
  const ModelRuntime runtime(male);
  Pose pose = rest_pose(male.model.skeleton);
  pose.local_rotations[5] *= 1.004f;  // within the daemon's 0.01 tolerance
  DeformJob job{.runtime = runtime, .pose = pose, .options = {.rotation_length_tolerance = 0.01}};
  const JobProblem problem = job.validate();
  EXPECT_FALSE(problem) << problem.message;
  // float normalisation: a few ulps.
  EXPECT_NEAR(glm::length(pose.local_rotations[5]), 1.0f, 1e-6f);
}

TEST(DeformJob, EachRefusedInputNamesItselfAndItsKind) {
  REQUIRE_SHARED_MALE();
  const ModelRuntime runtime(male);
  const int joints = male.model.skeleton.size();

  Pose pose = rest_pose(male.model.skeleton);
  pose.local_rotations.pop_back();
  JobProblem problem = DeformJob{.runtime = runtime, .pose = pose}.validate();
  EXPECT_EQ(problem.input, Input::kJointCount);
  EXPECT_TRUE(names(problem, std::to_string(joints - 1) + " rotations")) << problem.message;
  EXPECT_TRUE(names(problem, std::to_string(joints) + " joints")) << problem.message;

  pose = rest_pose(male.model.skeleton);
  pose.local_rotations[3] = glm::quat(std::numeric_limits<float>::quiet_NaN(), 0, 0, 0);
  problem = DeformJob{.runtime = runtime, .pose = pose}.validate();
  EXPECT_EQ(problem.input, Input::kPose);
  EXPECT_TRUE(names(problem, "joint 3 ('" + male.model.skeleton.joints[3].name + "')"))
      << problem.message;

  pose = rest_pose(male.model.skeleton);
  pose.root_translation.z = std::numeric_limits<float>::infinity();
  problem = DeformJob{.runtime = runtime, .pose = pose}.validate();
  EXPECT_EQ(problem.input, Input::kPose);
  EXPECT_TRUE(names(problem, "root translation")) << problem.message;

  pose = rest_pose(male.model.skeleton);
  problem = DeformJob{.runtime = runtime,
                      .pose = pose,
                      .method = DeformMethod::kDqs,
                      .features = {.folding = true}}
                .validate();
  EXPECT_EQ(problem.input, Input::kSelection);
  EXPECT_TRUE(names(problem, "sweep method only")) << problem.message;

  const std::vector<double> two_volumes(2, 0.0);
  problem = DeformJob{.runtime = runtime, .pose = pose, .options = {.added_volume = two_volumes}}
                .validate();
  EXPECT_EQ(problem.input, Input::kSelection);
  EXPECT_TRUE(names(problem, "2 added volumes")) << problem.message;
}

TEST(DeformJob, RotationsOutsideTheLengthToleranceAreRefusedNotNormalised) {
  REQUIRE_SHARED_MALE();
  const ModelRuntime runtime(male);
  Pose pose = rest_pose(male.model.skeleton);
  pose.local_rotations[4] = glm::quat(1.5f, 0, 0, 0);
  // Without a tolerance any non-zero length is a direction (a file's or a library caller's).
  EXPECT_FALSE((DeformJob{.runtime = runtime, .pose = pose}.validate()));
  EXPECT_NEAR(glm::length(pose.local_rotations[4]), 1.0f, 1e-6f);

  pose.local_rotations[4] = glm::quat(1.5f, 0, 0, 0);
  const JobProblem problem =
      DeformJob{.runtime = runtime, .pose = pose, .options = {.rotation_length_tolerance = 0.01}}
          .validate();
  EXPECT_EQ(problem.input, Input::kPose);
  EXPECT_TRUE(names(problem, "joint 4")) << problem.message;
  EXPECT_TRUE(names(problem, "length 1.5")) << problem.message;
  EXPECT_EQ(pose.local_rotations[4], glm::quat(1.5f, 0, 0, 0)) << "a refused pose is left as sent";
}

TEST(DeformJob, RunRefusesWhatValidateRefusesAndRunValidatedGuardsSizes) {
  REQUIRE_SHARED_MALE();
  const ModelRuntime runtime(male);
  DeformContext context;
  std::vector<glm::vec3> out(male.model.vertex_count());
  Pose pose = rest_pose(male.model.skeleton);
  pose.local_rotations[3] = glm::quat(0, 0, 0, 0);
  try {
    DeformJob{.runtime = runtime, .pose = pose, .positions = out}.run(context);
    FAIL() << "zero quaternion accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("invalid pose"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("zero-length"), std::string::npos) << e.what();
  }
  // run_validated trusts the values but not the sizes: a short buffer or a short pose is named.
  pose = rest_pose(male.model.skeleton);
  std::vector<glm::vec3> short_buffer(10);
  DeformJob short_output{.runtime = runtime, .pose = pose, .positions = short_buffer};
  EXPECT_THROW(short_output.run_validated(context), std::invalid_argument);
  pose.local_rotations.pop_back();
  DeformJob short_pose{.runtime = runtime, .pose = pose, .positions = out};
  EXPECT_THROW(short_pose.run_validated(context), std::invalid_argument);
  // Validated once, run without a second check: the same vertices as run().
  pose = rest_pose(male.model.skeleton);
  DeformJob job{.runtime = runtime, .pose = pose, .positions = out};
  ASSERT_FALSE(job.validate());
  job.run_validated(context);
  std::vector<glm::vec3> again(male.model.vertex_count());
  DeformJob{.runtime = runtime, .pose = pose, .positions = again}.run(context);
  EXPECT_EQ(out, again);
}

}  // namespace
}  // namespace sweepd::deform
