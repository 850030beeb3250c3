// The corpus's OpenPose body (issue 48: a one-joint torso, legs that are roots of their own,
// arms without hand joints) on both CMU clips: it binds, its torso and limbs are swept, and the
// sweep stretches its skin less than skinning does over each clip. Also mirrored and at 0.6x its
// size, so that nothing depends on which side is left or on the body's size (a ratio of
// lengths does not change with size, and the clip's root path is scaled to the hips' height).
//
// Figure: the largest edge stretch of a frame, |l / l_rest - 1| over the welded edges
// (QualityMeter::largest_edge_stretch), every 50th frame. Asserted per clip, sweep against the
// better of LBS and DQS, as length ratios l / l_rest:
// - the worst frame's ratio no more than 1.02x the baseline's (issue 47's gate; measured 4.82
//   against 11.37 on cmu_01_01, 3.57 against 16.21 on cmu_01_03; mirrored 3.86 / 8.19 and
//   3.99 / 11.20);
// - the mean over the frames of each frame's worst ratio no more than the baseline's (measured
//   2.42 against 5.11 and 2.79 against 6.83; mirrored 2.51 / 4.02 and 2.85 / 5.50);
// - no frame where the sweep's ratio is more than 1.02x the baseline's. With the torso left to
//   skinning (before its sweep ran up to the neck's base, RigMap::torso_sweep_chain) the armpit
//   stretched more than skinning where the arms go overhead (cmu_01_03 frame 3850: 10.5
//   against 7.1), in 11 of 56 and 27 of 91 frames; now in none.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "io/bvh/bvh_load.h"
#include "metrics/quality_metrics.h"
#include "metrics/region_quality.h"
#include "motion/retarget.h"
#include "tests/deform/shared_male.h"
#include "tests/mirrored_model.h"
#include "tests/rescaled_model.h"

namespace sweepd::metrics::one_joint_torso_clip_test {
namespace {

namespace fs = std::filesystem;
using deform::DeformMethod;

struct ClipFigures {
  double worst[3] = {0, 0, 0};  // per method (sweep, LBS, DQS): the largest ratio of any frame
  double mean[3] = {0, 0, 0};   // per method: the mean over frames of each frame's largest ratio
  int frames = 0, sweep_worse_frames = 0;
};

ClipFigures measure(const deform::BoundModel& bound, const fs::path& bvh) {
  const motion::Retargeter clip(io::load_bvh(bvh), bound.model);
  deform::test::Posing posing(bound);
  const QualityMeter meter(bound);
  std::vector<glm::vec3> positions(bound.model.vertex_count());
  ClipFigures f;
  for (int frame = 0; frame < clip.frame_count(); frame += 50) {
    double ratio[3];
    for (int m = 0; m < 3; ++m) {
      deform::Pose pose = clip.pose_at_frame(frame);
      posing.deform(pose, static_cast<DeformMethod>(m), positions);
      ratio[m] = 1.0 + meter.largest_edge_stretch(positions);
      f.worst[m] = std::max(f.worst[m], ratio[m]);
      f.mean[m] += ratio[m];
    }
    f.sweep_worse_frames += ratio[0] > 1.02 * std::min(ratio[1], ratio[2]);
    ++f.frames;
  }
  for (double& mean : f.mean) mean /= f.frames;
  return f;
}

enum class Variant { kAsIs, kMirrored, kSmaller };

std::string variant_name(Variant variant) {
  return variant == Variant::kAsIs ? "as_is" : variant == Variant::kMirrored ? "mirrored" : "smaller";
}

class OneJointTorsoClip : public testing::TestWithParam<Variant> {};

TEST_P(OneJointTorsoClip, SweepStretchesLessThanSkinningOverBothClips) {
  const fs::path file =
      fs::path(SWEEPD_SHARED_DATA) / "models/corpus/makehuman_female_slim_openpose.glb";
  if (!fs::exists(file)) GTEST_SKIP() << "shared data absent: " << file;
  deform::Model model = io::load_gltf(file);
  if (GetParam() == Variant::kMirrored) model = test_models::mirrored(std::move(model));
  if (GetParam() == Variant::kSmaller) model = test_models::rescaled(std::move(model), 0.6f);
  const deform::BoundModel bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  ASSERT_EQ(bound.sweeps.size(), 5u) << "the torso, both arms and both legs swept";
  // Issue 47 item 5: the torso's sweep spans the hips to the shoulders (MidHip up to the neck's
  // base), so the torso region is swept, not skinned: its mean skinned share was 0.982 when the
  // one-joint torso was left to skinning, 0.045 measured now; at most 0.1 (what the hand-overs
  // to the hips, shoulders and neck leave).
  EXPECT_EQ(bound.sweeps[0].part, deform::BodyPart::kTorso);
  EXPECT_EQ(bound.sweeps[0].chain, bound.rig.torso_sweep_chain());
  const RegionLabels labels = label_regions(bound);
  double torso_skinned = 0.0;
  int torso_vertices = 0;
  for (std::size_t v = 0; v < bound.vertices.size(); ++v)
    if (labels.regions[labels.region_of_vertex[v]] == deform::BodyPart::kTorso) {
      torso_skinned += bound.vertices[v].skin_weight;
      ++torso_vertices;
    }
  ASSERT_GT(torso_vertices, 0);
  std::printf("torso region: %d vertices, mean skinned share %.3f\n", torso_vertices,
              torso_skinned / torso_vertices);
  EXPECT_LE(torso_skinned / torso_vertices, 0.1);
  for (const char* name : {"cmu_01_01", "cmu_01_03"}) {
    SCOPED_TRACE(name);
    const ClipFigures f = measure(bound, fs::path(SWEEPD_SHARED_DATA) / "motion" /
                                             (std::string(name) + ".bvh"));
    const double worst_baseline = std::min(f.worst[1], f.worst[2]);
    const double mean_baseline = std::min(f.mean[1], f.mean[2]);
    std::printf("%s %s: worst ratio sweep %.2f lbs %.2f dqs %.2f; mean %.2f / %.2f / %.2f; "
                "sweep worse in %d of %d frames\n",
                name, variant_name(GetParam()).c_str(), f.worst[0], f.worst[1], f.worst[2],
                f.mean[0], f.mean[1], f.mean[2], f.sweep_worse_frames, f.frames);
    EXPECT_LE(f.worst[0], 1.02 * worst_baseline);
    EXPECT_LE(f.mean[0], mean_baseline);
    EXPECT_EQ(f.sweep_worse_frames, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Variants, OneJointTorsoClip,
                         testing::Values(Variant::kAsIs, Variant::kMirrored, Variant::kSmaller),
                         [](const testing::TestParamInfo<Variant>& info) {
                           return variant_name(info.param);
                         });

}  // namespace
}  // namespace sweepd::metrics::one_joint_torso_clip_test
