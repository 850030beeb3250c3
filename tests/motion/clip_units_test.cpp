// A clip's length unit and frame rate do not change what it does to the model: both shared CMU
// clips read in metres, centimetres and inches (io::BvhOptions::length_scale) and sampled at 30
// and 100 frames per second (Retargeter::pose_at_time, as `sweepctl pose --fps`) put the male's
// ankles and toes where the metre clip at the same times puts them, within 0.01 mm — so they
// stand on the same floor and take the same strides. (The root's translation is scaled by the
// ratio of the two skeletons' hip heights, legs included, measured in each one's own unit.)
// Z-up clips are not covered: the retargeter takes Y-up clips only.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "deform/model/forward_kinematics.h"
#include "io/bvh_load.h"
#include "io/gltf_load.h"
#include "motion/retarget.h"

namespace sweepd::motion {
namespace {

namespace fs = std::filesystem;

const fs::path kData = SWEEPD_SHARED_DATA;
constexpr float kMetresPerCmuUnit = 0.056444f;

TEST(ClipUnits, CentimetreAndInchClipsAtAnyRateMoveTheFeetAsTheMetreClip) {
  const fs::path male = kData / "models/makehuman_male_cmu.glb";
  if (!fs::exists(male)) GTEST_SKIP() << "shared data absent: " << male;
  const deform::Model model = io::load_gltf(male);
  std::vector<int> feet;
  for (const char* name : {"LeftFoot", "RightFoot", "LeftToeBase", "RightToeBase"})
    feet.push_back(model.skeleton.find(name));
  std::vector<glm::mat4> world(model.skeleton.joints.size());
  const auto foot_positions = [&](const deform::Pose& pose) {
    deform::forward_kinematics(model.skeleton, pose, world);
    std::vector<glm::vec3> positions;
    for (int j : feet) positions.emplace_back(world[j][3]);
    return positions;
  };
  for (const char* clip : {"cmu_01_01.bvh", "cmu_01_03.bvh"}) {
    const fs::path file = kData / "motion" / clip;
    if (!fs::exists(file)) GTEST_SKIP() << "shared data absent: " << file;
    const Retargeter metres(io::load_bvh(file, {.length_scale = kMetresPerCmuUnit}), model);
    for (const auto& [unit, scale] : {std::pair{"cm", kMetresPerCmuUnit * 100.0f},
                                      std::pair{"inch", kMetresPerCmuUnit / 0.0254f}}) {
      const Retargeter variant(io::load_bvh(file, {.length_scale = scale}), model);
      for (double fps : {30.0, 100.0}) {
        float worst = 0.0f;
        for (int f = 0; f / fps <= metres.duration(); ++f) {
          const std::vector<glm::vec3> a = foot_positions(metres.pose_at_time(f / fps));
          const std::vector<glm::vec3> b = foot_positions(variant.pose_at_time(f / fps));
          for (std::size_t i = 0; i < a.size(); ++i)
            worst = std::max(worst, glm::distance(a[i], b[i]));
        }
        std::printf("%s in %s at %.0f fps: feet differ from the metre clip's by at most %.2e m\n",
                    clip, unit, fps, worst);
        // Float round-off of a root scale that differs in its last bits, on a 2 m body
        // (measured below 1e-6 m).
        EXPECT_LT(worst, 1e-5f) << clip << " " << unit << " " << fps;
      }
    }
  }
}

}  // namespace
}  // namespace sweepd::motion
