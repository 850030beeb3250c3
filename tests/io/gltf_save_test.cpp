// save_gltf: round trips through load_gltf, and the Khronos glTF-Validator's verdict on what it
// writes (via tests/tools/validate_gltf.js, installed by deploy/install-deps.sh).
#include "io/gltf_save.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "io/gltf_load.h"
#include "mannequin/mannequin.h"
#include "tests/io/gltf_test_files.h"

namespace sweepd::io {
namespace {

using testing::ScratchDirectory;
using testing::shared_model;

// A tube along a chain of `joint_count` joints (each 0.1 m long, bent 10 degrees about z at
// each joint): 6 vertices per ring, one ring per joint plus one, weights blended between
// neighbouring joints. One vertex lists its joint twice, which the writer has to merge.
deform::Model synthetic_tube(int joint_count) {
  deform::Model model;
  model.name = "tube";
  for (int j = 0; j < joint_count; ++j) {
    deform::Joint joint;
    joint.name = "bone" + std::to_string(j);
    joint.parent = j - 1;
    joint.rest_translation = j == 0 ? glm::vec3(0.0f, 0.5f, 0.0f) : glm::vec3(0.0f, 0.1f, 0.0f);
    joint.rest_rotation = glm::angleAxis(glm::radians(10.0f), glm::vec3(0, 0, 1));
    model.skeleton.joints.push_back(joint);
  }
  const std::vector<glm::mat4> world = model.skeleton.world_rest_matrices();
  constexpr int kRing = 6;
  for (int r = 0; r <= joint_count; ++r) {
    const int j = std::min(r, joint_count - 1);
    const float along = r == joint_count ? 0.1f : 0.0f;
    for (int k = 0; k < kRing; ++k) {
      const float angle = glm::two_pi<float>() * k / kRing;
      const glm::vec4 local(0.03f * std::cos(angle), along, 0.03f * std::sin(angle), 1.0f);
      model.positions.push_back(glm::vec3(world[j] * local));
      model.uvs.push_back({k / float(kRing), r / float(joint_count)});
      const std::uint16_t previous = static_cast<std::uint16_t>(std::max(j - 1, 0));
      model.skin_joints.push_back({static_cast<std::uint16_t>(j), previous, 0, 0});
      model.skin_weights.push_back({0.7f, 0.3f, 0.0f, 0.0f});
    }
  }
  model.skin_joints[0] = {0, 0, 0, 0};  // joint 0 twice: 0.7 + 0.3
  for (int r = 0; r < joint_count; ++r)
    for (int k = 0; k < kRing; ++k) {
      const std::uint32_t a = r * kRing + k, b = r * kRing + (k + 1) % kRing;
      const std::uint32_t c = a + kRing, d = b + kRing;
      model.indices.insert(model.indices.end(), {a, c, b, b, c, d});
    }
  model.normals = deform::compute_vertex_normals(model.positions, model.indices);
  return model;
}

// Every stored quantity of `loaded` equals `original` to within `tolerance` (see callers).
void expect_same_model(const deform::Model& original, const deform::Model& loaded,
                       float tolerance) {
  ASSERT_EQ(loaded.vertex_count(), original.vertex_count());
  ASSERT_EQ(loaded.indices, original.indices);
  ASSERT_EQ(loaded.uvs.size(), original.uvs.size());
  ASSERT_EQ(loaded.skeleton.size(), original.skeleton.size());
  float worst = 0.0f;
  auto track = [&](float difference) { worst = std::max(worst, std::abs(difference)); };
  for (std::size_t v = 0; v < original.vertex_count(); ++v) {
    for (int c = 0; c < 3; ++c) {
      track(loaded.positions[v][c] - original.positions[v][c]);
      track(loaded.normals[v][c] - original.normals[v][c]);
    }
    if (original.has_uvs())
      for (int c = 0; c < 2; ++c) track(loaded.uvs[v][c] - original.uvs[v][c]);
    // Compare influences as joint -> weight sums, so merged repeats and reordering are equal.
    std::map<int, float> before, after;
    for (int k = 0; k < deform::kInfluences; ++k) {
      before[original.skin_joints[v][k]] += original.skin_weights[v][k];
      after[loaded.skin_joints[v][k]] += loaded.skin_weights[v][k];
    }
    for (auto& [joint, weight] : before) track(after[joint] - weight);
    for (auto& [joint, weight] : after) track(before[joint] - weight);
  }
  for (int j = 0; j < original.skeleton.size(); ++j) {
    const deform::Joint& a = original.skeleton.joints[j];
    const deform::Joint& b = loaded.skeleton.joints[j];
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.parent, a.parent);
    for (int c = 0; c < 3; ++c) {
      track(b.rest_translation[c] - a.rest_translation[c]);
      track(b.rest_scale[c] - a.rest_scale[c]);
    }
    for (int c = 0; c < 4; ++c) track(b.rest_rotation[c] - a.rest_rotation[c]);
  }
  EXPECT_LE(worst, tolerance);
}

TEST(GltfSave, MaleRoundTripIsLossless) {
  SWEEPD_REQUIRE_SHARED_MODEL(testing::kMale);
  ScratchDirectory dir;
  const deform::Model original = load_gltf(shared_model(testing::kMale));
  save_gltf(original, dir / "male.glb");
  LoadReport report;
  const deform::Model loaded = load_gltf(dir / "male.glb", &report);
  // Floats are stored as floats; the only arithmetic is world_rest * inverse(world_rest), which
  // is the identity to a few float ulps of 1 m-sized coordinates: 1e-6.
  expect_same_model(original, loaded, 1e-6f);
  EXPECT_EQ(report.renormalised_weight_count, 0);
  EXPECT_EQ(loaded.validate(), "");
}

TEST(GltfSave, RiggedFigureRoundTripKeepsTheFoldedRoot) {
  SWEEPD_REQUIRE_SHARED_MODEL(testing::kRiggedFigure);
  ScratchDirectory dir;
  const deform::Model original = load_gltf(shared_model(testing::kRiggedFigure));
  save_gltf(original, dir / "figure.glb");
  const deform::Model loaded = load_gltf(dir / "figure.glb");
  // Rotated joints: float inverse bind matrices along chains of up to 6 joints, coordinates
  // ~1 m, cost a few float ulps (3.7e-7 measured): 1e-6.
  expect_same_model(original, loaded, 1e-6f);
}

TEST(GltfSave, SyntheticTubeRoundTripMergesRepeatedJoints) {
  ScratchDirectory dir;
  const deform::Model original = synthetic_tube(5);
  ASSERT_EQ(original.validate(), "");
  save_gltf(original, dir / "tube.glb");
  const deform::Model loaded = load_gltf(dir / "tube.glb");
  // Chain of 5 joints of 10 degrees each, coordinates < 1 m: a few float ulps, below 1e-6.
  expect_same_model(original, loaded, 1e-6f);
  EXPECT_EQ(loaded.skin_joints[0][0], 0);
  EXPECT_FLOAT_EQ(loaded.skin_weights[0][0], 1.0f);  // 0.7 + 0.3 merged
}

TEST(GltfSave, RejectsAnInvalidModel) {
  ScratchDirectory dir;
  deform::Model model = synthetic_tube(2);
  model.skin_weights[3] = {0.5f, 0.0f, 0.0f, 0.0f};
  EXPECT_THROW(save_gltf(model, dir / "bad.glb"), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.glb"));
  SaveOptions options;
  options.vertex_colors.resize(3);
  EXPECT_THROW(save_gltf(synthetic_tube(2), dir / "bad.glb", options), std::invalid_argument);
}

TEST(GltfSave, UnwritablePathThrows) {
  ScratchDirectory dir;
  EXPECT_THROW(save_gltf(synthetic_tube(2), dir / "no_such_dir" / "x.glb"), std::runtime_error);
}

// The Khronos validator's summary of one file, or a reason why it cannot run (then empty json).
struct ValidatorRun {
  nlohmann::json summary;
  std::string skip_reason;
};

ValidatorRun run_validator(const std::filesystem::path& file) {
  const std::filesystem::path source = SWEEPD_SOURCE_DIR;
  const std::filesystem::path modules = source / ".tools" / "node_modules";
  if (std::system("command -v node >/dev/null 2>&1") != 0)
    return {{}, "node is not on PATH; the glTF validator cannot run"};
  if (!std::filesystem::exists(modules / "gltf-validator"))
    return {
        {},
        "gltf-validator not installed in " + modules.string() + " (run deploy/install-deps.sh)"};
  const std::string command = "NODE_PATH='" + modules.string() + "' node '" +
                              (source / "tests" / "tools" / "validate_gltf.js").string() + "' '" +
                              file.string() + "'";
  std::string output;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char chunk[4096];
    while (std::size_t n = std::fread(chunk, 1, sizeof chunk, pipe)) output.append(chunk, n);
    pclose(pipe);
  }
  ValidatorRun run;
  run.summary = nlohmann::json::parse(output, nullptr, false);
  return run;
}

void expect_validator_accepts(const std::filesystem::path& file) {
  const ValidatorRun run = run_validator(file);
  if (!run.skip_reason.empty()) GTEST_SKIP() << run.skip_reason;
  ASSERT_TRUE(run.summary.is_object()) << "validator output is not JSON: " << run.summary;
  EXPECT_EQ(run.summary["errors"], 0) << run.summary["messages"].dump(1);
  EXPECT_EQ(run.summary["warnings"], 0) << run.summary["messages"].dump(1);
}

TEST(GltfSaveValidator, MaleRoundTripHasNoErrors) {
  SWEEPD_REQUIRE_SHARED_MODEL(testing::kMale);
  ScratchDirectory dir;
  save_gltf(load_gltf(shared_model(testing::kMale)), dir / "male.glb");
  expect_validator_accepts(dir / "male.glb");
}

TEST(GltfSaveValidator, RiggedFigureWithRenormalisedWeightsHasNoErrors) {
  SWEEPD_REQUIRE_SHARED_MODEL(testing::kRiggedFigure);
  ScratchDirectory dir;
  save_gltf(load_gltf(shared_model(testing::kRiggedFigure)), dir / "figure.glb");
  expect_validator_accepts(dir / "figure.glb");  // the source file has 31 errors
}

TEST(GltfSaveValidator, SyntheticTubeWithColoursHasNoErrors) {
  ScratchDirectory dir;
  const deform::Model tube = synthetic_tube(5);
  SaveOptions options;
  options.vertex_colors.assign(tube.vertex_count(), glm::vec4(0.2f, 0.4f, 0.8f, 1.0f));
  save_gltf(tube, dir / "tube.glb", options);
  expect_validator_accepts(dir / "tube.glb");
}

TEST(GltfSaveValidator, MannequinAt72kVerticesWithLineLoopsHasNoErrors) {
  // The acceptance for the mannequin, plus the line loops of `bind --debug-gltf`.
  ScratchDirectory dir;
  const deform::Model mannequin = mannequin::make_mannequin({.target_vertices = 72000});
  SaveOptions options;
  options.line_loops = {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {{0, 2, 0}, {0, 2, 1}}};
  save_gltf(mannequin, dir / "mannequin.glb", options);
  expect_validator_accepts(dir / "mannequin.glb");
  EXPECT_EQ(load_gltf(dir / "mannequin.glb").vertex_count(), mannequin.vertex_count());
}

TEST(GltfSaveValidator, ThreeHundredJointsUseShortJointIndices) {
  ScratchDirectory dir;
  const deform::Model tube = synthetic_tube(300);  // > 256 joints: JOINTS_0 as u16
  save_gltf(tube, dir / "long_tube.glb");
  expect_validator_accepts(dir / "long_tube.glb");
  const deform::Model loaded = load_gltf(dir / "long_tube.glb");
  EXPECT_EQ(loaded.skin_joints.back()[0], 299);
}

TEST(GltfSaveValidator, ReportsErrorsInABadFile) {
  // The check above can fail: the validator does find the source RiggedFigure's 31 errors.
  SWEEPD_REQUIRE_SHARED_MODEL(testing::kRiggedFigure);
  const ValidatorRun run = run_validator(shared_model(testing::kRiggedFigure));
  if (!run.skip_reason.empty()) GTEST_SKIP() << run.skip_reason;
  ASSERT_TRUE(run.summary.is_object());
  EXPECT_EQ(run.summary["errors"], 31);  // SOURCES.md: 31 ACCESSOR_WEIGHTS_NON_NORMALIZED
}

}  // namespace
}  // namespace sweepd::io
