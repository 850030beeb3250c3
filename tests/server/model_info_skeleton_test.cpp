// ModelInfo carries the rest skeleton and floor (protocol 1.1): a client rebuilds them exactly,
// so the served model is the model (a clip retargeted onto them moves as on the model file).
#include <gtest/gtest.h>

#include <filesystem>

#include "cli/served_rest_skeleton.h"
#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "motion/retarget.h"
#include "server/replies/model_info.h"

namespace sweepd::test {
namespace {

namespace fs = std::filesystem;
namespace pb = sweepd::protocol;

TEST(ModelInfoSkeleton, RebuildsTheMalesSkeletonAndRetargetsLikeTheLibrary) {
  const fs::path data(SWEEPD_SHARED_DATA);
  const fs::path male = data / "models/makehuman_male_cmu.glb";
  if (!fs::exists(male)) GTEST_SKIP() << "shared data absent: " << male;
  const deform::Model model = io::load_gltf(male);
  server::RegisteredModel registered{
      .id = 7, .content_id = std::string(64, 'a'), .name = "male", .bound = {}, .bind_time_ns = 0};
  registered.bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  flatbuffers::FlatBufferBuilder builder;
  server::build_model_info(builder, registered, 1);
  const pb::ModelInfo& info =
      *pb::GetSizePrefixedMessage(builder.GetBufferPointer())->body_as_ModelInfo();

  // Floats travel unchanged through FlatBuffers: the skeleton comes back bit-exact.
  const deform::Skeleton skeleton = cli::rest_skeleton(info);
  ASSERT_EQ(skeleton.size(), model.skeleton.size());
  for (int j = 0; j < skeleton.size(); ++j) {
    const deform::Joint &got = skeleton.joints[j], &want = model.skeleton.joints[j];
    EXPECT_EQ(got.name, want.name);
    EXPECT_EQ(got.parent, want.parent);
    EXPECT_EQ(got.rest_translation, want.rest_translation) << want.name;
    EXPECT_EQ(got.rest_rotation, want.rest_rotation) << want.name;
    EXPECT_EQ(got.rest_scale, want.rest_scale) << want.name;
  }

  // The same inputs (skeleton, floor, motion) → the same poses, bit for bit. A bare skeleton
  // has no soles to plant, so the model's retargeting is compared with its feet free.
  const io::BvhOptions cmu{.length_scale = 0.056444f};
  const motion::Clip motion = io::load_bvh(data / "motion/cmu_01_01.bvh", cmu);
  const motion::Retargeter remote(motion, cli::rest_skeleton(info), {}, info.floor_height());
  const motion::Retargeter local(motion, model, {}, motion::Feet::kFree);
  for (int frame : {0, 600, 1257}) {
    const deform::Pose a = remote.pose_at_frame(frame), b = local.pose_at_frame(frame);
    EXPECT_EQ(a.root_translation, b.root_translation) << frame;
    for (std::size_t j = 0; j < a.local_rotations.size(); ++j)
      EXPECT_EQ(a.local_rotations[j], b.local_rotations[j]) << frame << " joint " << j;
  }
}

TEST(ModelInfoSkeleton, AServerWithoutTheRestSkeletonIsAClearError) {
  flatbuffers::FlatBufferBuilder builder;
  const std::vector<std::int32_t> parents{-1};
  builder.Finish(pb::CreateModelInfoDirect(builder, 1, "old", nullptr, &parents));
  const pb::ModelInfo& info = *flatbuffers::GetRoot<pb::ModelInfo>(builder.GetBufferPointer());
  try {
    cli::rest_skeleton(info);
    FAIL() << "no exception";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("protocol 1.0"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace sweepd::test
