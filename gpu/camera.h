// Camera: view and projection matrices for previews and camera-space position maps, the
// default camera that frames a mesh from the front, and a camera framing a box from any
// direction (contact sheets: the same scale in every cell, close-ups of a joint).
//
// Conventions: right-handed world, Y up, models face +Z (glTF). view maps world to camera space
// (camera looks down -Z); projection is an OpenGL clip-space projection (z in [-w, w]).
#pragma once

#include <glm/glm.hpp>
#include <span>

namespace sweepd::gpu {

struct Camera {
  glm::mat4 view{1.0f};
  glm::mat4 projection{1.0f};
};

// A perspective camera on the +Z side of the positions' bounding box, looking at its centre,
// placed so the box's bounding sphere fits the view for this aspect (width / height) and
// vertical field of view. positions: V points, V >= 1.
Camera front_camera(std::span<const glm::vec3> positions, float aspect,
                    float vertical_fov_degrees = 30.0f);

// A perspective camera on the side `towards_eye` (a non-zero direction) of `centre`, looking at
// it with Y up (+Z up when towards_eye is vertical), as near as it can be while a box around
// the centre with half_extents (x: along the view's right, y: its up, z: towards the eye; each
// > 0) fits the view for this aspect (width / height) and vertical field of view. Depth spans
// the box with its depth to spare on either side.
Camera box_camera(glm::vec3 centre, glm::vec3 half_extents, glm::vec3 towards_eye, float aspect,
                  float vertical_fov_degrees = 30.0f);

}  // namespace sweepd::gpu
