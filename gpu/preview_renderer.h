// PreviewRenderer: a shaded picture of a posed mesh, for people to look at deformations
// (`sweepctl render`), written with io::write_png.
//
// Inputs (PreviewMesh): positions V×3, normals V×3, indices 3F, and optionally per-vertex
//   colours V×3 in [0, 1] (segmentation, binding regions, collision overlays); without them
//   every vertex has options.base_colour.
// Options: image size; camera (default: front_camera framing the mesh's bounding box from +Z);
//   background RGBA; Lambert + ambient shading from a light fixed relative to the camera
//   (two-sided: normals facing away from the eye are flipped); MSAA samples (1 = none).
// Output: rgba, W·H·4 bytes, caller-owned, row 0 = top row (ready for io::write_png). A pixel
//   covered by the mesh is colour · (ambient + (1 - ambient) · max(0, n·l)); others are the
//   background.
// Construct and use on the thread where the Context is current; it must not outlive the Context.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <span>
#include <string>

#include "gpu/camera.h"
#include "gpu/egl_context.h"
#include "gpu/mesh_buffers.h"
#include "gpu/shader_program.h"

namespace sweepd::gpu {

struct PreviewMesh {
  std::span<const glm::vec3> positions;
  std::span<const glm::vec3> normals;
  std::span<const std::uint32_t> indices;
  std::span<const glm::vec3> vertex_colours;  // empty: base_colour everywhere
};

struct PreviewOptions {
  int width = 800;
  int height = 800;
  std::optional<Camera> camera;
  glm::vec4 background{0.9f, 0.9f, 0.92f, 1.0f};
  glm::vec3 base_colour{0.78f, 0.74f, 0.70f};
  float ambient = 0.25f;
  glm::vec3 light_direction{-0.3f, 0.5f, 1.0f};  // towards the light, camera space
  int samples = 4;
};

class PreviewRenderer {
 public:
  explicit PreviewRenderer(const Context& context);
  ~PreviewRenderer();
  PreviewRenderer(const PreviewRenderer&) = delete;
  PreviewRenderer& operator=(const PreviewRenderer&) = delete;

  // Empty when mesh, options and the output size fit together; otherwise the reason.
  std::string validate(const PreviewMesh& mesh, const PreviewOptions& options,
                       std::span<const std::uint8_t> rgba) const;
  // Renders and reads back into rgba; throws std::invalid_argument with validate()'s reason.
  void render(const PreviewMesh& mesh, const PreviewOptions& options, std::span<std::uint8_t> rgba);

 private:
  void resize_targets(int width, int height, int samples);
  void delete_targets();

  const GlFunctions& gl_;
  GLint max_size_ = 0, max_samples_ = 0;
  ShaderProgram shade_;
  MeshBuffers mesh_;
  int width_ = 0, height_ = 0, samples_ = 0;
  // Renderbuffers: multisampled colour and depth, single-sampled colour to resolve into.
  GLuint renderbuffers_[3] = {};
  GLuint framebuffers_[2] = {};  // drawing (multisampled), resolved
};

}  // namespace sweepd::gpu
