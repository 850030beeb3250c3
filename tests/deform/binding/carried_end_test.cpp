// Ends carried by a limb's or the neck's last bone (deform/binding/carried_end.h): on the corpus's
// OpenPose body (its forearm bones carry the hands, its neck bone the head), as is, mirrored and
// at 0.6x, the wrist and the neck's top are found where they are on the mesh, and bind with
// sweep_carried_ends sweeps the forearms and the neck up to them.
#include "deform/binding/carried_end.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "deform/binding/bind.h"
#include "deform/mesh/welded_mesh.h"
#include "deform/rig/rig_map.h"
#include "io/gltf/gltf_load.h"
#include "tests/body_variants.h"

namespace sweepd::deform {
namespace {

namespace fs = std::filesystem;

const fs::path kOpenPose =
    fs::path(SWEEPD_SHARED_DATA) / "models/corpus/makehuman_female_slim_openpose.glb";

std::vector<test_models::BodyVariant> openpose_variants() {
  static const Model model = io::load_gltf(kOpenPose);
  return test_models::plain_mirrored_and_rescaled({{"openpose", &model}}, 0.6f);
}

float scale_of(const test_models::BodyVariant& variant) {
  return variant.name.ends_with("x0.6") ? 0.6f : 1.0f;
}

TEST(CarriedEnd, FindsTheWristsAndTheNecksTopOnTheOpenPoseBody) {
  if (!fs::exists(kOpenPose)) GTEST_SKIP() << "shared data absent: " << kOpenPose;
  for (const test_models::BodyVariant& variant : openpose_variants()) {
    const Model& model = variant.model;
    const RigMap rig = detect_rig_map(model.skeleton);
    const std::vector<glm::mat4> world_rest = model.skeleton.world_rest_matrices();
    const WeldedMesh mesh = weld_mesh(model.positions, model.indices);
    const float scale = scale_of(variant);
    float wrist_fraction[2];
    for (int side = 0; side < 2; ++side) {
      const int forearm = (side == 0 ? rig.left_arm : rig.right_arm).lower;
      ASSERT_GE(forearm, 0);
      const CarriedEnd wrist =
          find_carried_end(model, mesh, world_rest, forearm, CarriedEndKind::kHand);
      ASSERT_TRUE(wrist.found) << variant.name << ": " << wrist.problem;
      std::printf("%s %s wrist: %.3f of elbow to fingertips, section %.2f cm2\n",
                  variant.name.c_str(), side == 0 ? "left" : "right", wrist.fraction,
                  1e4 * wrist.section_area);
      // Measured 0.53 (sampled every 0.019), section 10.0 cm² at full size: the narrowest
      // before the palm; the palm's sections are 18-22 cm², the elbow's 32.
      EXPECT_NEAR(wrist.fraction, 0.53f, 0.04f) << variant.name;
      EXPECT_NEAR(1e4f * wrist.section_area / (scale * scale), 10.0f, 1.5f) << variant.name;
      wrist_fraction[side] = wrist.fraction;
    }
    // Left and right are mirror images of each other: within one sample.
    EXPECT_NEAR(wrist_fraction[0], wrist_fraction[1], 0.02f) << variant.name;

    ASSERT_EQ(rig.neck.chain.size(), 1u);
    const CarriedEnd neck =
        find_carried_end(model, mesh, world_rest, rig.neck.head, CarriedEndKind::kHead);
    ASSERT_TRUE(neck.found) << variant.name << ": " << neck.problem;
    std::printf("%s neck's top: %.3f of neck base to crown, section %.2f cm2\n",
                variant.name.c_str(), neck.fraction, 1e4 * neck.section_area);
    // Measured 0.35, 53 cm², 11 cm above the neck's joint: under the jaw (its next section out
    // cuts the mouth's inside), well above the trapezius (240-500 cm² below 0.15).
    EXPECT_NEAR(neck.fraction, 0.35f, 0.04f) << variant.name;
    EXPECT_NEAR(1e4f * neck.section_area / (scale * scale), 53.0f, 6.0f) << variant.name;
  }
}

TEST(CarriedEnd, BindSweepsTheForearmsAndTheNeckOnToTheirEnds) {
  if (!fs::exists(kOpenPose)) GTEST_SKIP() << "shared data absent: " << kOpenPose;
  for (const test_models::BodyVariant& variant : openpose_variants()) {
    const Model& model = variant.model;
    const RigMap rig = detect_rig_map(model.skeleton);
    const BoundModel plain = bind(model, rig);
    const BoundModel carried = bind(model, rig, {}, {}, true);
    // The neck gets a sweep of its own (joint key, two link keys, the end's); each arm's runs on
    // past the elbow with three keys more.
    ASSERT_EQ(carried.sweeps.size(), plain.sweeps.size() + 1) << variant.name;
    int ending = 0;
    for (const BoundSweep& sweep : carried.sweeps) {
      if (!sweep.ends_on_carried_end()) continue;
      ++ending;
      EXPECT_EQ(sweep.rest_keys.size(), sweep.part == BodyPart::kNeck ? 4u : 7u) << variant.name;
    }
    EXPECT_EQ(ending, 3) << variant.name;
    // The rest pose is rebuilt from the bindings as exactly as without the ends (float rounding).
    const std::vector<glm::vec3> rest = rest_positions_from_binding(carried);
    float worst = 0.0f;
    for (std::size_t v = 0; v < rest.size(); ++v)
      worst = std::max(worst, glm::length(rest[v] - model.positions[v]));
    EXPECT_LT(worst, 1e-5f) << variant.name;
    // Vertices left wholly to skinning: fewer by the forearms and the neck (measured 10,773 ->
    // 10,183 of 14,517 at every size; the hands' 1,500 each and the head stay skinned).
    auto skinned_whole = [](const BoundModel& bound) {
      int n = 0;
      for (const VertexBinding& b : bound.vertices) n += b.skin_weight >= 1.0f;
      return n;
    };
    std::printf("%s: skinned whole %d -> %d of %zu vertices\n", variant.name.c_str(),
                skinned_whole(plain), skinned_whole(carried), model.vertex_count());
    EXPECT_LT(skinned_whole(carried), skinned_whole(plain) - 500) << variant.name;
  }
}

}  // namespace
}  // namespace sweepd::deform
