// ModelService without a process: the default mannequin, and key-ellipse edits — refused ones
// change nothing, an accepted one is swapped in as a new handle (the old one stays whole for
// whoever holds it) and is on disk for the next start.
#include "server/models/model_service.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <optional>

#include "io/gltf/gltf_save.h"
#include "mannequin/mannequin.h"
#include "server/models/content_id.h"
#include "tests/scratch_directory.h"

namespace sweepd::test {
namespace {

server::ServerConfig config_in(const std::filesystem::path& store) {
  server::ServerConfig config;
  config.store_dir = store;
  config.mannequin_vertices = 2000;  // small: binding it is quick
  return config;
}

// The code an edit is refused with, or none when it is accepted.
std::optional<protocol::ErrorCode> refusal(server::ModelService& models, std::uint32_t id,
                                           const deform::RestKeyEdit& edit) {
  try {
    models.edit_key_ellipse(id, edit);
  } catch (const server::ModelError& error) {
    return error.code();
  }
  return std::nullopt;
}

TEST(ModelService, KeyEllipseEditsAreCheckedSwappedInAndStored) {
  const ScratchDirectory directory("model_service");
  const server::ServerConfig config = config_in(directory);
  server::ModelService models(config);
  models.restore();
  models.add_default_model();
  ASSERT_EQ(models.models().size(), 1u);
  const server::ModelHandle before = models.models().front();
  EXPECT_EQ(before->name, "mannequin");

  int arm = -1;
  for (std::size_t s = 0; s < before->bound.sweeps.size(); ++s)
    if (before->bound.sweeps[s].part == deform::BodyPart::kLeftArm) arm = static_cast<int>(s);
  ASSERT_GE(arm, 0);
  const float old_a = before->bound.sweeps[arm].rest_keys[0].a;
  deform::RestKeyEdit edit;
  edit.sweep = "left_arm";
  edit.key = 0;
  edit.a = 1.25f * old_a;

  EXPECT_EQ(refusal(models, before->id + 100, edit), protocol::ErrorCode::UnknownModel);
  deform::RestKeyEdit unknown_sweep = edit;
  unknown_sweep.sweep = "tail";
  EXPECT_EQ(refusal(models, before->id, unknown_sweep), protocol::ErrorCode::InvalidArgument);
  EXPECT_EQ(models.find(before->id), before);  // refused: the same model, untouched

  const server::ModelHandle after = models.edit_key_ellipse(before->id, edit);
  EXPECT_NE(after, before);
  EXPECT_EQ(models.find(before->id), after);
  // Exact: the edit sets the half-axis to the given float, and the old handle is a separate copy.
  EXPECT_EQ(after->bound.sweeps[arm].rest_keys[0].a, edit.a);
  EXPECT_EQ(before->bound.sweeps[arm].rest_keys[0].a, old_a);

  server::ModelService restarted(config);
  restarted.restore();
  ASSERT_TRUE(restarted.find(before->id));
  EXPECT_EQ(restarted.find(before->id)->bound.sweeps[arm].rest_keys[0].a, edit.a);
}

TEST(ModelService, BindsAnUploadWithTheOrientationCurveItAsksFor) {
  const ScratchDirectory directory("model_service_orientation");
  const server::ServerConfig config = config_in(directory);
  server::ModelService models(config);
  models.restore();
  const ScratchDirectory glb_directory("model_service_glb");
  const std::filesystem::path glb = glb_directory / "small.glb";
  io::save_gltf(mannequin::make_mannequin({.target_vertices = 2000}), glb);
  std::ifstream in(glb, std::ios::binary);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in),
                                        std::istreambuf_iterator<char>()};
  server::ModelLoadRequest request;
  request.name = "small";
  request.gltf = bytes;
  const server::ModelHandle linear = models.load(request);
  EXPECT_EQ(linear->bound.options.orientation_curve, deform::OrientationCurveKind::kLinear);
  // The linear curve leaves the content id as it was before the option existed.
  EXPECT_EQ(linear->content_id, server::model_content_id(bytes, "", 0));
  request.name = "small_smooth";
  request.orientation = 1;
  const server::ModelHandle smooth = models.load(request);
  EXPECT_EQ(smooth->bound.options.orientation_curve, deform::OrientationCurveKind::kSmooth);
  EXPECT_NE(smooth->content_id, linear->content_id);  // another binding, another id
  request.orientation = 2;
  try {
    models.load(request);
    ADD_FAILURE() << "orientation 2 was accepted";
  } catch (const server::ModelError& error) {
    EXPECT_EQ(error.code(), protocol::ErrorCode::ModelLoadFailed);
    EXPECT_NE(std::string(error.what()).find("orientation curve 2"), std::string::npos);
  }
}

}  // namespace
}  // namespace sweepd::test
