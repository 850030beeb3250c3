// Tests for gpu::box_camera: the box's corners land inside the view, touching its edge along
// the axis that binds, from any viewing direction (pure matrix arithmetic, no GL).
#include "gpu/camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace sweepd::gpu {
namespace {

struct Extent {
  float x = 0, y = 0;            // largest |NDC x|, |NDC y| over the corners
  float near_z = 1, far_z = -1;  // NDC depth range of the corners
};

Extent project_corners(const Camera& camera, glm::vec3 centre, glm::vec3 right, glm::vec3 up,
                       glm::vec3 towards_eye, glm::vec3 half) {
  Extent extent;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p = centre + (corner & 1 ? 1.0f : -1.0f) * half.x * right +
                        (corner & 2 ? 1.0f : -1.0f) * half.y * up +
                        (corner & 4 ? 1.0f : -1.0f) * half.z * towards_eye;
    const glm::vec4 clip = camera.projection * camera.view * glm::vec4(p, 1.0f);
    const glm::vec3 ndc = glm::vec3(clip) / clip.w;
    extent.x = std::max(extent.x, std::abs(ndc.x));
    extent.y = std::max(extent.y, std::abs(ndc.y));
    extent.near_z = std::min(extent.near_z, ndc.z);
    extent.far_z = std::max(extent.far_z, ndc.z);
  }
  return extent;
}

TEST(BoxCamera, FitsATallBoxByHeightAndAWideOneByWidthFromAnySide) {
  const glm::vec3 centre(0.3f, 0.9f, -0.2f);
  // A body-like box (0.3 wide, 0.9 tall, 0.25 deep half sides) seen from the front (+Z) in a
  // portrait cell binds vertically; a wide box seen from +X (its right is -Z) binds sideways.
  struct Case {
    glm::vec3 towards_eye, right, half;
    float aspect;
    bool binds_vertically;
  };
  for (const Case& c : {Case{{0, 0, 1}, {1, 0, 0}, {0.3f, 0.9f, 0.25f}, 0.75f, true},
                        Case{{1, 0, 0}, {0, 0, -1}, {1.2f, 0.4f, 0.3f}, 1.0f, false}}) {
    const Camera camera = box_camera(centre, c.half, c.towards_eye, c.aspect);
    const Extent e = project_corners(camera, centre, c.right, {0, 1, 0}, c.towards_eye, c.half);
    // The near face's corners touch the view's edge on the binding axis (float rounding: 1e-5)
    // and stay inside on the other; every corner lies between the near and far planes.
    EXPECT_NEAR(c.binds_vertically ? e.y : e.x, 1.0f, 1e-5f);
    EXPECT_LT(c.binds_vertically ? e.x : e.y, 1.0f);
    EXPECT_GT(e.near_z, -1.0f);
    EXPECT_LT(e.far_z, 1.0f);
  }
}

}  // namespace
}  // namespace sweepd::gpu
