// The armpits of the shared male under both shared CMU clips: with the arms raised (cmu_01_03
// frames 1089 and 3898, the upper arm 98° and 104° from its clavicle) the skin where the arm
// sweep meets the torso stretched 3.5x with sweeps and 6.3x with LBS. A third of that skin is
// skinned after blending, with the painted weights that jump across the armpit; the skinned
// share now follows those weights smoothed over the shoulder ring (skinned_share_influences.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "deform/binding/bind.h"
#include "deform/job/deform_job.h"
#include "deform/rig/rig_map.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "motion/retarget.h"
#include "tests/deform/mesh_edges.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

namespace fs = std::filesystem;

const fs::path kData(SWEEPD_SHARED_DATA);

const BoundModel& bound_male() {
  static const BoundModel bound = [] {
    const Model model = io::load_gltf(kData / "models/makehuman_male_cmu.glb");
    return bind(model, detect_rig_map(model.skeleton));
  }();
  return bound;
}

bool shared_data_present() { return fs::exists(kData / "models/makehuman_male_cmu.glb"); }

using test::MeshEdge;

// The edges clip_deformation_test reports as "left arm" and "right arm": their first vertex's
// heaviest painted joint belongs to an arm.
std::vector<MeshEdge> arm_edges(const BoundModel& bound) {
  const std::vector<BodyPart> joint_part = label_joints(bound.rig, bound.model.skeleton);
  std::vector<MeshEdge> edges;
  for (const MeshEdge& e : test::distinct_edges(bound.model)) {
    const BodyPart part = test::heaviest_part(bound.model, joint_part, e.a);
    if (part == BodyPart::kLeftArm || part == BodyPart::kRightArm) edges.push_back(e);
  }
  return edges;
}

float stretch(const MeshEdge& e, std::span<const glm::vec3> positions) {
  return glm::length(positions[e.a] - positions[e.b]) / e.rest_length;
}

TEST(ArmpitStretch, RaisedArmsStretchNoArmEdgeOver3xOnEitherClip) {
  if (!shared_data_present()) GTEST_SKIP() << "shared data absent: " << kData;
  const BoundModel& bound = bound_male();
  test::Posing deformer(bound);
  const std::vector<MeshEdge> edges = arm_edges(bound);
  std::vector<glm::vec3> positions(bound.model.vertex_count());
  for (const char* clip : {"motion/cmu_01_01.bvh", "motion/cmu_01_03.bvh"}) {
    const motion::Retargeter retargeter(io::load_bvh(kData / clip), bound.model);
    float worst[2] = {0.0f, 0.0f};  // sweep, lbs
    int worst_frame = -1;
    const MeshEdge* worst_edge = nullptr;
    for (int frame = 0; frame < retargeter.frame_count(); ++frame)
      for (DeformMethod method : {DeformMethod::kSweep, DeformMethod::kLbs}) {
        Pose pose = retargeter.pose_at_frame(frame);
        deformer.deform(pose, method, positions, {});
        const int m = method == DeformMethod::kSweep ? 0 : 1;
        for (const MeshEdge& e : edges) {
          const float s = stretch(e, positions);
          if (s <= worst[m]) continue;
          worst[m] = s;
          if (m == 0) worst_frame = frame, worst_edge = &e;
        }
      }
    ASSERT_NE(worst_edge, nullptr);
    std::printf("%s arms: sweep %.3fx (frame %d, edge %u-%u) | lbs %.3fx\n", clip, worst[0],
                worst_frame, worst_edge->a, worst_edge->b, worst[1]);
    // Issue 4's bound on every edge; 3.51x (cmu_01_03 frame 1089, edge 8904-8918) with the
    // painted weights in the skinned share.
    EXPECT_LE(worst[0], 3.0f) << clip;
    EXPECT_LT(worst[0], worst[1]) << clip << ": the sweeps tear the armpit less than LBS";
  }
}

TEST(ArmpitStretch, TheWorstRaisedArmFramesEachSide) {
  if (!shared_data_present()) GTEST_SKIP() << "shared data absent: " << kData;
  const BoundModel& bound = bound_male();
  test::Posing deformer(bound);
  const motion::Retargeter retargeter(io::load_bvh(kData / "motion/cmu_01_03.bvh"), bound.model);
  std::vector<glm::vec3> positions(bound.model.vertex_count());
  struct Case {
    int frame;
    MeshEdge edge;
  };
  // The armpit edges that stretched most on main (left and right mirror each other).
  for (Case c : {Case{1089, {8904, 8918, 0.0f}}, Case{3898, {1658, 1674, 0.0f}}}) {
    c.edge.rest_length =
        glm::length(bound.model.positions[c.edge.a] - bound.model.positions[c.edge.b]);
    float by_method[2];
    for (DeformMethod method : {DeformMethod::kSweep, DeformMethod::kLbs}) {
      Pose pose = retargeter.pose_at_frame(c.frame);
      deformer.deform(pose, method, positions, {});
      by_method[method == DeformMethod::kSweep ? 0 : 1] = stretch(c.edge, positions);
    }
    std::printf("frame %d edge %u-%u (rest %.2f mm): sweep %.3fx | lbs %.3fx\n", c.frame, c.edge.a,
                c.edge.b, 1e3f * c.edge.rest_length, by_method[0], by_method[1]);
    // Was 3.51x / 3.47x; now 2.86x. 2.9x leaves a margin for float rounding between compilers.
    EXPECT_LE(by_method[0], 2.9f) << "frame " << c.frame;
  }
}

TEST(ArmpitStretch, SkinnedShareWeightsAreThePaintedOnesSmoothedOnlyAroundTheShoulders) {
  if (!shared_data_present()) GTEST_SKIP() << "shared data absent: " << kData;
  const BoundModel& bound = bound_male();
  const Model& model = bound.model;
  ASSERT_EQ(bound.skinned_share_weights.size(), model.vertex_count());
  ASSERT_EQ(bound.skinned_share_joints.size(), model.vertex_count());
  std::size_t changed = 0;
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    const VertexBinding& b = bound.vertices[v];
    bool arm = false, torso = false;
    for (int k = 0; k < kSweepsPerVertex; ++k) {
      if (b.sweep[k] < 0 || b.weight[k] <= 0.0f) continue;
      const BodyPart part = bound.sweeps[b.sweep[k]].part;
      arm |= part == BodyPart::kLeftArm || part == BodyPart::kRightArm;
      torso |= part == BodyPart::kTorso;
    }
    float sum = 0.0f;
    for (float w : bound.skinned_share_weights[v]) sum += w;
    EXPECT_NEAR(sum, 1.0f, 1e-5f) << v << ": weights are renormalised";
    const bool same = bound.skinned_share_weights[v] == model.skin_weights[v] &&
                      bound.skinned_share_joints[v] == model.skin_joints[v];
    // Outside the ring (no arm or no torso share, or nothing skinned: the wrists, the shoulder
    // tops) the painted weights, bit for bit.
    if (!arm || !torso || b.skin_weight <= 0.0f) {
      EXPECT_TRUE(same) << v;
    }
    changed += !same;
  }
  std::printf("%zu of %zu vertices follow smoothed weights in their skinned share\n", changed,
              model.vertex_count());
  EXPECT_GT(changed, 0u);
  // Across the worst armpit edge the spine's weight jumped 0.12 -> 0.33; smoothing narrows it.
  auto spine_weight = [&](const auto& joints, const auto& weights, std::uint32_t v) {
    const int spine = model.skeleton.find("Spine");
    float w = 0.0f;
    for (int k = 0; k < kInfluences; ++k) w += joints[v][k] == spine ? weights[v][k] : 0.0f;
    return w;
  };
  const float painted = std::abs(spine_weight(model.skin_joints, model.skin_weights, 8904) -
                                 spine_weight(model.skin_joints, model.skin_weights, 8918));
  const float smoothed =
      std::abs(spine_weight(bound.skinned_share_joints, bound.skinned_share_weights, 8904) -
               spine_weight(bound.skinned_share_joints, bound.skinned_share_weights, 8918));
  std::printf("spine weight jump across edge 8904-8918: painted %.3f, smoothed %.3f\n", painted,
              smoothed);
  EXPECT_LT(smoothed, 0.5f * painted);
}

}  // namespace
}  // namespace sweepd::deform
