// The contact sheet looks at the body's front, found from the body (deform::rest_body_axes), not
// assumed +Z: a character modelled facing +X (or turned 180°) was drawn from its side (or back).
// The cells are captured from DrawCell, so no GL is needed.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "gpu/sheet/contact_sheet.h"
#include "mannequin/mannequin.h"
#include "tests/limbs_flexed.h"
#include "tests/turned_model.h"

namespace sweepd::sheet {
namespace {

// The flattened direction from the camera's target box to its eye, for azimuth 0 (the front).
glm::vec3 eye_direction_of_the_cell(const deform::Model& model, float azimuth_degrees) {
  const deform::BoundModel bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  const deform::ModelRuntime runtime(bound);
  deform::Pose pose = deform::test::elbows_and_knees_flexed(bound, 0.0f);
  SheetOptions options;
  options.methods.push_back(deform::methods_by_name().at("sweep"));
  options.frames = {0};
  options.cell_width = options.cell_height = 64;
  options.azimuth_degrees = azimuth_degrees;
  std::vector<glm::mat4> views;
  ContactSheet sheet(
      {bound, runtime, [&](int) { return pose; }}, options, nullptr,
      [&](const gpu::PreviewMesh&, const gpu::PreviewOptions& preview, std::span<std::uint8_t>) {
        views.push_back(preview.camera.value().view);
      });
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(sheet.width()) * options.cell_height * 4);
  sheet.render_row(0, rgba, 0);
  EXPECT_EQ(views.size(), 1u);
  if (views.empty()) return glm::vec3(0.0f);
  glm::vec3 low = model.positions.front(), high = low;
  for (const glm::vec3& p : model.positions) low = glm::min(low, p), high = glm::max(high, p);
  const glm::vec3 eye(glm::inverse(views[0])[3]);
  glm::vec3 towards_eye = eye - 0.5f * (low + high);
  towards_eye.y = 0.0f;
  return glm::normalize(towards_eye);
}

TEST(ContactSheetFraming, TheEyeIsInFrontOfTheBodyHoweverItWasModelledFacing) {
  const deform::Model mannequin = mannequin::make_mannequin({.target_vertices = 4000});
  for (const float degrees : {0.0f, 90.0f, 180.0f, -90.0f}) {
    const glm::vec3 front =
        glm::angleAxis(glm::radians(degrees), glm::vec3(0, 1, 0)) * glm::vec3(0, 0, 1);
    const glm::vec3 left = glm::cross(glm::vec3(0, 1, 0), front);
    const deform::Model model = test_models::turned(mannequin, degrees);
    // Within 2°: the front is found from the arms' rest positions (the mannequin's are level and
    // symmetric, so it is exact up to float rounding); the camera is placed along it.
    EXPECT_GT(glm::dot(eye_direction_of_the_cell(model, 0.0f), front), std::cos(glm::radians(2.0f)))
        << "modelled facing " << degrees << "° from +Z: the sheet must look at its front";
    // azimuth 90 is the body's left side, whichever way it was modelled.
    EXPECT_GT(glm::dot(eye_direction_of_the_cell(model, 90.0f), left), std::cos(glm::radians(2.0f)))
        << "modelled facing " << degrees << "° from +Z, azimuth 90";
  }
}

}  // namespace
}  // namespace sweepd::sheet
