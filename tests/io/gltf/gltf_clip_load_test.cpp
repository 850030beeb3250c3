// io::load_gltf_clip and the glTF spec's sampling (motion/keyframe_track.h), on a glTF made in
// the test (tests/io/baked_gltf_clip.h: cmu_01_01 retargeted onto the shared male and baked as
// LINEAR, STEP and CUBICSPLINE animations of the male's own joints):
// - at its key times each animation gives its keys exactly (bit for bit);
// - between keys it matches the spec's interpolation within 1e-6, computed here another way
//   (slerp as q0 (q0⁻¹ q1)^s through an axis and angle; the cubic Hermite as a Bézier curve by
//   de Casteljau) — 1e-6 since both sides round to float from double;
// - the clip's joints are the model's (same names, order, rest), so OwnSkeletonClip plays it,
//   and a frame index lands on its key (frames 1/30 s apart, from the key spacing);
// - retargeted onto the model it came from (--clip-from), rotations come back within 1e-5;
// - errors name the problem: no such name or index (listing the file's animations), key times
//   that do not increase, a wrong output count, an unknown interpolation.
#include "io/gltf/gltf_clip_load.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "deform/rig/rig_map.h"
#include "io/gltf/gltf_load.h"
#include "motion/own_skeleton_clip.h"
#include "motion/retarget.h"
#include "tests/io/baked_gltf_clip.h"
#include "tests/io/gltf_test_files.h"

namespace sweepd::io {
namespace {

using testing::BakedClip;

constexpr int kKeys = 12;

class GltfClipTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(testing::shared_model(testing::kMale)) ||
        !std::filesystem::exists(std::filesystem::path(SWEEPD_SHARED_DATA) /
                                 "motion/cmu_01_01.bvh"))
      GTEST_SKIP() << "shared test data absent (see ../shared/data/SOURCES.md)";
    model_ = load_gltf(testing::shared_model(testing::kMale));
    baked_ = testing::bake_cmu_clip(model_, kKeys);
    file_ = scratch_ / "baked.glb";
    testing::write_baked_gltf(model_, baked_, file_);
  }

  std::string refusal(const std::filesystem::path& file, const std::string& clip) const {
    try {
      load_gltf_clip(file, clip);
    } catch (const LoadError& error) {
      return error.what();
    }
    return "(loaded)";
  }

  // A copy of the baked file with `change` applied to its "linear" animation (index 0).
  std::filesystem::path broken(const std::string& name,
                               const std::function<void(tinygltf::Model&)>& change) const {
    tinygltf::Model gltf = testing::read_glb(file_);
    change(gltf);
    const std::filesystem::path out = scratch_ / name;
    testing::write_glb(gltf, out);
    return out;
  }

  testing::ScratchDirectory scratch_;
  deform::Model model_;
  BakedClip baked_;
  std::filesystem::path file_;
};

// q0 (q0⁻¹ q1)^s, on the shorter arc: the spec's slerp by another road.
glm::dquat reference_slerp(glm::dquat q0, glm::dquat q1, double s) {
  // Unit in double first, and the half angle from the sine: keys a few 1e-5 rad apart whose
  // float lengths exceed 1 by 4e-8 gave r.w > 1, which acos read as no turn at all.
  q0 = glm::normalize(q0);
  q1 = glm::normalize(q1);
  glm::dquat r = glm::conjugate(q0) * q1;
  if (r.w < 0.0) r = -r;
  const double sin_half = glm::length(glm::dvec3(r.x, r.y, r.z));
  const double half = std::atan2(sin_half, r.w);
  if (sin_half < 1e-15) return q0;
  const glm::dvec3 axis = glm::dvec3(r.x, r.y, r.z) / sin_half;
  const double turned = s * half;
  return q0 * glm::dquat(std::cos(turned), axis * std::sin(turned));
}

// The Hermite segment as a cubic Bézier curve evaluated by de Casteljau.
template <typename V>
V reference_hermite(V v0, V out_tangent, V in_tangent, V v1, double td, double s) {
  const V p[4] = {v0, v0 + out_tangent * (td / 3.0), v1 - in_tangent * (td / 3.0), v1};
  const V a = p[0] + (p[1] - p[0]) * s, b = p[1] + (p[2] - p[1]) * s, c = p[2] + (p[3] - p[2]) * s;
  const V d = a + (b - a) * s, e = b + (c - b) * s;
  return d + (e - d) * s;
}

glm::dquat dq(const glm::quat& q) { return glm::dquat(q.w, q.x, q.y, q.z); }

double quat_gap(const glm::quat& a, const glm::dquat& b) {
  double gap = 0.0;
  for (int i = 0; i < 4; ++i) gap = std::max(gap, std::abs(double{a[i]} - b[i]));
  return gap;
}

TEST_F(GltfClipTest, TheClipsJointsAreTheModelsAndItsFramesItsKeys) {
  const motion::Clip clip = load_gltf_clip(file_, "linear");
  ASSERT_EQ(clip.joints.size(), model_.skeleton.joints.size());
  for (std::size_t j = 0; j < clip.joints.size(); ++j) {
    EXPECT_EQ(clip.joints[j].name, model_.skeleton.joints[j].name);
    EXPECT_EQ(clip.joints[j].parent, model_.skeleton.joints[j].parent);
  }
  EXPECT_EQ(clip.tracks.size(), model_.skeleton.joints.size() + 1);
  EXPECT_EQ(clip.frame_count, kKeys);
  EXPECT_NEAR(clip.frames_per_second(), 30.0f, 1e-3f);
  EXPECT_TRUE(clip.warnings.empty());
  EXPECT_EQ(load_gltf_clip(file_, "2").tracks.front().interpolation,
            motion::Interpolation::kCubicSpline);
}

TEST_F(GltfClipTest, AtItsKeyTimesEachAnimationGivesItsKeysExactly) {
  for (const char* name : {"linear", "step", "cubic"}) {
    const motion::OwnSkeletonClip clip(load_gltf_clip(file_, name), model_.skeleton);
    for (int k = 0; k < kKeys; ++k)
      for (const deform::Pose& pose : {clip.pose_at_time(baked_.times[k]), clip.pose_at_frame(k)}) {
        ASSERT_EQ(pose.local_rotations.size(), baked_.rotations[k].size());
        for (std::size_t j = 0; j < pose.local_rotations.size(); ++j)
          ASSERT_EQ(pose.local_rotations[j], baked_.rotations[k][j]) << name << " key " << k;
        ASSERT_EQ(pose.root_translation, baked_.root[k]) << name << " key " << k;
      }
  }
}

TEST_F(GltfClipTest, BetweenKeysEachAnimationFollowsTheSpecsInterpolation) {
  const motion::OwnSkeletonClip linear(load_gltf_clip(file_, "linear"), model_.skeleton);
  const motion::OwnSkeletonClip step(load_gltf_clip(file_, "step"), model_.skeleton);
  const motion::OwnSkeletonClip cubic(load_gltf_clip(file_, "cubic"), model_.skeleton);
  double worst_linear = 0.0, worst_cubic = 0.0, worst_step = 0.0;
  for (int k = 0; k + 1 < kKeys; ++k)
    for (double s : {0.1, 0.37, 0.5, 0.83}) {
      const double td = double{baked_.times[k + 1]} - baked_.times[k];
      const double t = baked_.times[k] + s * td;
      const deform::Pose l = linear.pose_at_time(t), c = cubic.pose_at_time(t),
                         st = step.pose_at_time(t);
      for (std::size_t j = 0; j < l.local_rotations.size(); ++j) {
        const glm::dquat q0 = dq(baked_.rotations[k][j]), q1 = dq(baked_.rotations[k + 1][j]);
        worst_linear =
            std::max(worst_linear, quat_gap(l.local_rotations[j], reference_slerp(q0, q1, s)));
        const glm::dquat hermite = glm::normalize(reference_hermite(
            q0, dq(baked_.rotation_slope[k][j]), dq(baked_.rotation_slope[k + 1][j]), q1, td, s));
        worst_cubic = std::max(worst_cubic, quat_gap(c.local_rotations[j], hermite));
        worst_step = std::max(worst_step, quat_gap(st.local_rotations[j], q0));
      }
      const glm::dvec3 r0(baked_.root[k]), r1(baked_.root[k + 1]);
      const glm::dvec3 lerped = r0 + (r1 - r0) * s;
      const glm::dvec3 curve = reference_hermite(r0, glm::dvec3(baked_.root_slope[k]),
                                                 glm::dvec3(baked_.root_slope[k + 1]), r1, td, s);
      for (int i = 0; i < 3; ++i) {
        worst_linear = std::max(worst_linear, std::abs(l.root_translation[i] - lerped[i]));
        worst_cubic = std::max(worst_cubic, std::abs(c.root_translation[i] - curve[i]));
        worst_step = std::max(worst_step, std::abs(double{st.root_translation[i]} - r0[i]));
      }
    }
  EXPECT_LT(worst_linear, 1e-6);
  EXPECT_LT(worst_cubic, 1e-6);
  EXPECT_EQ(worst_step, 0.0);
}

// With its feet free; planted, the feet go to the floor where this clip (played twice as fast
// as the frames it was baked from) sets one down, which bends the legs, and nothing else moves.
TEST_F(GltfClipTest, RetargetedOntoItsOwnModelTheRotationsComeBack) {
  const motion::Clip motion = load_gltf_clip(file_, "linear");
  const motion::Retargeter clip(motion, model_, {}, motion::Feet::kFree);
  const motion::Retargeter planted(motion, model_);
  const deform::RigMap map = deform::detect_rig_map(model_.skeleton);
  const auto in_a_leg = [&](int joint) {
    for (const deform::LegJoints* leg : {&map.left_leg, &map.right_leg})
      if (joint == leg->upper || joint == leg->lower || joint == leg->foot) return true;
    return false;
  };
  double worst = 0.0, worst_planted = 0.0;
  for (int k = 0; k < kKeys; ++k) {
    const deform::Pose pose = clip.pose_at_frame(k), planted_pose = planted.pose_at_frame(k);
    for (std::size_t j = 0; j < pose.local_rotations.size(); ++j) {
      bool driven = false;  // unmapped and undriven joints keep their rest rotation
      for (const motion::JointMatch& match : clip.matches())
        driven |= match.model_joint == static_cast<int>(j) && match.driven;
      if (!driven) continue;
      const float dot = std::abs(glm::dot(pose.local_rotations[j], baked_.rotations[k][j]));
      worst = std::max(worst, 1.0 - double{dot});
      if (in_a_leg(static_cast<int>(j))) continue;
      const float same =
          std::abs(glm::dot(planted_pose.local_rotations[j], baked_.rotations[k][j]));
      worst_planted = std::max(worst_planted, 1.0 - double{same});
    }
    EXPECT_EQ(planted_pose.root_translation.x, pose.root_translation.x);
    EXPECT_EQ(planted_pose.root_translation.z, pose.root_translation.z);
  }
  // 1 - |cos(θ/2)| below 1e-5: rotations within 0.5° (float round-off through the world
  // rotations and back; measured 1e-7).
  EXPECT_LT(worst, 1e-5);
  EXPECT_LT(worst_planted, 1e-5);
}

TEST_F(GltfClipTest, UnknownClipsAreRefusedListingTheFilesAnimations) {
  EXPECT_NE(
      refusal(file_, "walk")
          .find(
              "no animation named 'walk' (the file's animations: 0 'linear', 1 'step', 2 'cubic')"),
      std::string::npos)
      << refusal(file_, "walk");
  EXPECT_NE(refusal(file_, "3").find("no animation 3: the file has 3"), std::string::npos)
      << refusal(file_, "3");
  EXPECT_NE(refusal(testing::shared_model(testing::kMale), "0").find("the file has no animations"),
            std::string::npos);
}

TEST_F(GltfClipTest, MalformedAnimationsAreRefusedNamingTheProblem) {
  const auto sampler_of_channel = [](tinygltf::Model & gltf, int channel) -> auto& {
    return gltf.animations[0].samplers[gltf.animations[0].channels[channel].sampler];
  };
  const std::filesystem::path backwards = broken("backwards.glb", [&](tinygltf::Model& gltf) {
    const int input = sampler_of_channel(gltf, 3).input;
    tinygltf::Accessor& times = gltf.accessors[input];
    const tinygltf::BufferView& view = gltf.bufferViews[times.bufferView];
    float* values = reinterpret_cast<float*>(gltf.buffers[0].data.data() + view.byteOffset);
    std::swap(values[4], values[5]);
  });
  EXPECT_NE(refusal(backwards, "linear").find("key times are not strictly increasing (key 5"),
            std::string::npos)
      << refusal(backwards, "linear");
  const std::filesystem::path short_output = broken("short.glb", [&](tinygltf::Model& gltf) {
    gltf.accessors[sampler_of_channel(gltf, 2).output].count -= 1;
  });
  EXPECT_NE(refusal(short_output, "linear").find("channel 2 (rotation of node 2 '"),
            std::string::npos);
  EXPECT_NE(refusal(short_output, "linear").find("11 outputs for 12 keys (expected 12)"),
            std::string::npos)
      << refusal(short_output, "linear");
  const std::filesystem::path bogus = broken("bogus.glb", [&](tinygltf::Model& gltf) {
    sampler_of_channel(gltf, 0).interpolation = "BOGUS";
  });
  EXPECT_NE(refusal(bogus, "linear").find("unknown interpolation 'BOGUS'"), std::string::npos)
      << refusal(bogus, "linear");
}

}  // namespace
}  // namespace sweepd::io
