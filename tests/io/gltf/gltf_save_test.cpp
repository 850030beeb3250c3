// save_gltf: round trips through load_gltf, and the Khronos glTF-Validator's verdict on what it
// writes (via tests/tools/validate_gltf.js, installed by deploy/install-deps.sh).
#include "io/gltf/gltf_save.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <glm/gtc/quaternion.hpp>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "io/gltf/gltf_clip_load.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "motion/own_skeleton_clip.h"
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

// Keys of synthetic_tube(5)'s joints bone0..bone4: LINEAR rotations of bone1..bone3 and the root
// bone0's LINEAR translation at 0, 0.5 and 1 s (one shared input), a STEP rotation of bone4 at 0
// and 0.4 s (its own input).
constexpr float kSwingTimes[] = {0.0f, 0.5f, 1.0f};

std::vector<float> xyzw(const glm::quat& q) { return {q.x, q.y, q.z, q.w}; }

motion::KeyframeTrack rotation_keys(int joint, motion::Interpolation interpolation,
                                    std::vector<float> times, glm::vec3 axis,
                                    std::vector<float> degrees) {
  motion::KeyframeTrack track;
  track.joint = joint;
  track.path = motion::TrackPath::kRotation;
  track.interpolation = interpolation;
  track.times = std::move(times);
  for (float angle : degrees) {
    const std::vector<float> q = xyzw(glm::angleAxis(glm::radians(angle), glm::normalize(axis)));
    track.values.insert(track.values.end(), q.begin(), q.end());
  }
  return track;
}

SavedAnimation swing_animation() {
  using motion::Interpolation;
  const std::vector<float> times(std::begin(kSwingTimes), std::end(kSwingTimes));
  SavedAnimation swing{"swing", {}};
  swing.tracks.push_back(rotation_keys(1, Interpolation::kLinear, times, {0, 0, 1}, {10, 40, -20}));
  swing.tracks.push_back(rotation_keys(2, Interpolation::kLinear, times, {1, 0, 0}, {0, 60, 15}));
  swing.tracks.push_back(rotation_keys(3, Interpolation::kLinear, times, {1, 2, 3}, {-30, 5, 70}));
  motion::KeyframeTrack root;
  root.joint = 0;
  root.path = motion::TrackPath::kTranslation;
  root.times = times;
  root.values = {0.0f, 0.5f, 0.0f, 0.1f, 0.55f, 0.0f, 0.2f, 0.5f, -0.1f};
  swing.tracks.push_back(root);
  swing.tracks.push_back(rotation_keys(4, Interpolation::kStep, {0.0f, 0.4f}, {0, 1, 0}, {0, 45}));
  return swing;
}

// The JSON chunk of a .glb (12-byte header, then the chunk's length and type, then the JSON).
nlohmann::json glb_json(const std::filesystem::path& file) {
  const std::string bytes = testing::read_bytes(file);
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, sizeof length);
  return nlohmann::json::parse(bytes.substr(20, length));
}

TEST(GltfSave, AnimationRoundTripsThroughTheClipLoader) {
  ScratchDirectory dir;
  const deform::Model tube = synthetic_tube(5);
  SaveOptions options;
  options.animations = {swing_animation()};
  save_gltf(tube, dir / "swing.glb", options);

  const motion::Clip clip = load_gltf_clip(dir / "swing.glb", "swing");
  const std::vector<motion::KeyframeTrack>& written = options.animations[0].tracks;
  ASSERT_EQ(clip.tracks.size(), written.size());
  // Exact: keys are float32 in the file as in memory, and load_gltf_clip does no arithmetic on
  // the tube's joints (scene-root chain, unit scales: nothing to carry them through).
  for (std::size_t t = 0; t < written.size(); ++t) {
    EXPECT_EQ(clip.tracks[t].joint, written[t].joint) << "track " << t;
    EXPECT_EQ(clip.tracks[t].path, written[t].path) << "track " << t;
    EXPECT_EQ(clip.tracks[t].interpolation, written[t].interpolation) << "track " << t;
    EXPECT_EQ(clip.tracks[t].times, written[t].times) << "track " << t;
    EXPECT_EQ(clip.tracks[t].values, written[t].values) << "track " << t;
  }

  // Tracks with the same times share their input; every input has its bounds.
  const nlohmann::json gltf = glb_json(dir / "swing.glb");
  std::set<int> inputs;
  for (const nlohmann::json& sampler : gltf["animations"][0]["samplers"])
    inputs.insert(sampler["input"].get<int>());
  EXPECT_EQ(inputs.size(), 2u);
  for (int input : inputs) {
    EXPECT_TRUE(gltf["accessors"][input].contains("min"));
    EXPECT_TRUE(gltf["accessors"][input].contains("max"));
  }

  // Between keys the reloaded model's own-skeleton player gives the pose the keys give: slerp
  // (glm's, float) and lerp of the written keys, STEP's earlier key, rest rotations elsewhere.
  // 1e-6 per component: float slerp against the player's double one, rounded to float.
  const deform::Model loaded = load_gltf(dir / "swing.glb");
  const motion::OwnSkeletonClip player(clip, loaded.skeleton);
  const auto key = [&](int track, int k) {
    const float* v = written[track].values.data() + 4 * k;
    return glm::quat(v[3], v[0], v[1], v[2]);
  };
  for (const float seconds : {0.25f, 0.75f}) {
    const int k = seconds < 0.5f ? 0 : 1;
    const float s = (seconds - kSwingTimes[k]) / (kSwingTimes[k + 1] - kSwingTimes[k]);
    std::vector<glm::quat> expected = {
        loaded.skeleton.joints[0].rest_rotation, glm::slerp(key(0, k), key(0, k + 1), s),
        glm::slerp(key(1, k), key(1, k + 1), s), glm::slerp(key(2, k), key(2, k + 1), s),
        key(4, seconds < 0.4f ? 0 : 1)};
    const float* root = written[3].values.data();
    const glm::vec3 root_expected =
        glm::mix(glm::vec3(root[3 * k], root[3 * k + 1], root[3 * k + 2]),
                 glm::vec3(root[3 * k + 3], root[3 * k + 4], root[3 * k + 5]), s);
    const deform::Pose pose = player.pose_at_time(seconds);
    ASSERT_EQ(pose.local_rotations.size(), expected.size());
    for (std::size_t j = 0; j < expected.size(); ++j)
      for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(pose.local_rotations[j][c], expected[j][c], 1e-6)
            << "joint " << j << " component " << c << " at " << seconds << " s";
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(pose.root_translation[c], root_expected[c], 1e-6) << "root at " << seconds;
  }
}

TEST(GltfSave, AcceptsARotationWithinTheUnitTolerance) {
  ScratchDirectory dir;
  SaveOptions options;
  options.animations = {swing_animation()};
  for (float& value : options.animations[0].tracks[0].values) value *= 1.0009f;
  EXPECT_NO_THROW(save_gltf(synthetic_tube(5), dir / "nearly_unit.glb", options));
}

TEST(GltfSave, RefusesBadAnimationsNamingTheProblem) {
  struct Case {
    std::function<void(std::vector<SavedAnimation>&)> spoil;
    std::string words;  // what the message must say
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float infinity = std::numeric_limits<float>::infinity();
  const std::vector<Case> cases = {
      {[](auto& a) { a[0].tracks[1].times[2] = 0.5f; },
       "animation 'swing' track 1 (rotation of joint 'bone2'): key times are not strictly "
       "increasing"},
      {[](auto& a) { a[0].tracks[3].values.pop_back(); },
       "animation 'swing' track 3 (translation of joint 'bone0'): 2 outputs for 3 keys"},
      {[](auto& a) { a[0].tracks[2].joint = 5; },
       "animation 'swing' track 2 (rotation): joint 5 is out of range (the model has 5 joints)"},
      {[](auto& a) { a[0].tracks[2].joint = -1; }, "joint -1 is out of range"},
      {[](auto& a) { a[0].name.clear(); }, "animation 0 has no name"},
      {[](auto& a) { a.push_back(a[0]); }, "two animations are named 'swing'"},
      {[](auto& a) { a[0].tracks.clear(); }, "animation 'swing' has no tracks"},
      {[](auto& a) {
         for (int i = 4; i < 8; ++i) a[0].tracks[0].values[i] *= 1.01f;
       },
       "track 0 (rotation of joint 'bone1'): key 1's rotation is not a unit quaternion (length "
       "1.010000"},
      {[&](auto& a) { a[0].tracks[3].values[4] = nan; },
       "track 3 (translation of joint 'bone0'): an output value is not finite"},
      {[&](auto& a) { a[0].tracks[0].values[0] = infinity; },
       "track 0 (rotation of joint 'bone1'): an output value is not finite"},
      {[&](auto& a) { a[0].tracks[4].times[1] = infinity; },
       "track 4 (rotation of joint 'bone4'): key time 1 is not finite"},
      {[](auto& a) { a[0].tracks[4].times[0] = -0.1f; },
       "track 4 (rotation of joint 'bone4'): key time 0 is negative"},
      {[](auto& a) {
         motion::KeyframeTrack& cubic = a[0].tracks[4];
         cubic.interpolation = motion::Interpolation::kCubicSpline;
         cubic.times = {0.0f};
         cubic.values = {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0};
       },
       "track 4 (rotation of joint 'bone4'): a CUBICSPLINE track needs 2 keys or more"},
      {[](auto& a) { a[0].tracks.push_back(a[0].tracks[2]); },
       "track 5 (rotation of joint 'bone3'): that joint has an earlier rotation track"},
  };
  ScratchDirectory dir;
  const deform::Model tube = synthetic_tube(5);
  for (const Case& bad : cases) {
    SaveOptions options;
    options.animations = {swing_animation()};
    bad.spoil(options.animations);
    try {
      save_gltf(tube, dir / "bad.glb", options);
      ADD_FAILURE() << "saved despite: " << bad.words;
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find(bad.words), std::string::npos)
          << "message: " << error.what() << "\nexpected it to say: " << bad.words;
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.glb")) << bad.words;
  }
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

TEST(GltfSaveValidator, AnimationOfRotationsTranslationAndStepHasNoErrors) {
  ScratchDirectory dir;
  SaveOptions options;
  options.animations = {swing_animation()};
  // A second animation, CUBICSPLINE: tangents (zero, or not unit) sit beside the unit values.
  motion::KeyframeTrack cubic =
      rotation_keys(2, motion::Interpolation::kCubicSpline, {0.0f, 1.0f}, {0, 0, 1}, {0, 90});
  const std::vector<float> zero(4, 0.0f), tangent = {0.0f, 0.0f, 0.5f, 0.0f};
  cubic.values.insert(cubic.values.begin() + 4, tangent.begin(), tangent.end());
  cubic.values.insert(cubic.values.begin(), zero.begin(), zero.end());
  cubic.values.insert(cubic.values.end() - 4, tangent.begin(), tangent.end());
  cubic.values.insert(cubic.values.end(), zero.begin(), zero.end());
  options.animations.push_back({"cubic", {cubic}});
  save_gltf(synthetic_tube(5), dir / "swing.glb", options);
  expect_validator_accepts(dir / "swing.glb");
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
