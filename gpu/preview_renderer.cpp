#include "gpu/preview_renderer.h"

#include <algorithm>
#include <glm/gtc/type_ptr.hpp>
#include <stdexcept>

namespace sweepd::gpu {
namespace {

constexpr const char* kShadeVertex = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 colour;
uniform mat4 view;
uniform mat4 projection;
uniform mat3 normal_matrix;
out vec3 v_position;  // camera space
out vec3 v_normal;
out vec3 v_colour;
void main() {
  vec4 camera_position = view * vec4(position, 1.0);
  v_position = camera_position.xyz;
  v_normal = normal_matrix * normal;
  v_colour = colour;
  gl_Position = projection * camera_position;
}
)";

constexpr const char* kShadeFragment = R"(#version 450 core
in vec3 v_position;
in vec3 v_normal;
in vec3 v_colour;
uniform vec3 light_direction;  // unit, camera space
uniform float ambient;
uniform bool perspective;
layout(location = 0) out vec4 out_colour;
void main() {
  vec3 n = normalize(v_normal);
  vec3 to_eye = perspective ? -v_position : vec3(0.0, 0.0, 1.0);
  if (dot(n, to_eye) < 0.0) n = -n;  // two-sided
  float lambert = max(dot(n, light_direction), 0.0);
  out_colour = vec4(v_colour * (ambient + (1.0 - ambient) * lambert), 1.0);
}
)";

enum Renderbuffer { kColour, kDepth, kResolved };
enum Framebuffer { kDraw, kResolve };

}  // namespace

PreviewRenderer::PreviewRenderer(const Context& context)
    : gl_(context.gl()), shade_(gl_, "preview", kShadeVertex, kShadeFragment), mesh_(gl_) {
  gl_.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size_);
  gl_.GetIntegerv(GL_MAX_SAMPLES, &max_samples_);
}

PreviewRenderer::~PreviewRenderer() { delete_targets(); }

void PreviewRenderer::delete_targets() {
  gl_.DeleteFramebuffers(2, framebuffers_);
  gl_.DeleteRenderbuffers(3, renderbuffers_);
  width_ = height_ = samples_ = 0;
}

void PreviewRenderer::resize_targets(int width, int height, int samples) {
  if (width == width_ && height == height_ && samples == samples_) return;
  delete_targets();
  gl_.GenRenderbuffers(3, renderbuffers_);
  const GLenum formats[3] = {GL_RGBA8, GL_DEPTH_COMPONENT24, GL_RGBA8};
  for (int r = 0; r < 3; ++r) {
    gl_.BindRenderbuffer(GL_RENDERBUFFER, renderbuffers_[r]);
    gl_.RenderbufferStorageMultisample(GL_RENDERBUFFER, r == kResolved ? 0 : samples, formats[r],
                                       width, height);
  }
  gl_.GenFramebuffers(2, framebuffers_);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffers_[kDraw]);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              renderbuffers_[kColour]);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              renderbuffers_[kDepth]);
  const bool draw_complete = gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffers_[kResolve]);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              renderbuffers_[kResolved]);
  if (!draw_complete || gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    delete_targets();
    throw std::runtime_error("preview: " + std::to_string(width) + "x" + std::to_string(height) +
                             " render targets with " + std::to_string(samples) +
                             " samples are not supported by this GL driver");
  }
  width_ = width;
  height_ = height;
  samples_ = samples;
}

std::string PreviewRenderer::validate(const PreviewMesh& mesh, const PreviewOptions& options,
                                      std::span<const std::uint8_t> rgba) const {
  if (options.width < 1 || options.height < 1 || options.width > max_size_ ||
      options.height > max_size_) {
    return "preview size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
           " is outside 1.." + std::to_string(max_size_);
  }
  if (options.samples < 1) return "samples must be at least 1";
  const std::size_t vertices = mesh.positions.size();
  if (vertices == 0) return "the mesh has no vertices";
  for (const std::string& problem :
       {check_vertex_count("normals", mesh.normals.size(), vertices),
        mesh.vertex_colours.empty()
            ? std::string()
            : check_vertex_count("colours", mesh.vertex_colours.size(), vertices),
        check_triangle_indices(mesh.indices, vertices)}) {
    if (!problem.empty()) return problem;
  }
  if (rgba.size() != static_cast<std::size_t>(options.width) * options.height * 4) {
    return "the image buffer is not W*H*4 bytes";
  }
  return {};
}

void PreviewRenderer::render(const PreviewMesh& mesh, const PreviewOptions& options,
                             std::span<std::uint8_t> rgba) {
  if (const std::string problem = validate(mesh, options, rgba); !problem.empty()) {
    throw std::invalid_argument("preview: " + problem);
  }
  const int samples = std::min(options.samples, std::max(max_samples_, 1));
  resize_targets(options.width, options.height, samples > 1 ? samples : 0);
  const Camera camera = options.camera.value_or(front_camera(
      mesh.positions, static_cast<float>(options.width) / static_cast<float>(options.height)));

  gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffers_[kDraw]);
  gl_.Viewport(0, 0, width_, height_);
  gl_.Enable(GL_DEPTH_TEST);
  gl_.DepthFunc(GL_LESS);
  gl_.Disable(GL_CULL_FACE);
  gl_.Disable(GL_BLEND);
  if (samples > 1) gl_.Enable(GL_MULTISAMPLE);
  const float depth_one = 1.0f;
  gl_.ClearBufferfv(GL_COLOR, 0, glm::value_ptr(options.background));
  gl_.ClearBufferfv(GL_DEPTH, 0, &depth_one);

  mesh_.set_attribute(0, as_floats(mesh.positions), 3);
  mesh_.set_attribute(1, as_floats(mesh.normals), 3);
  if (mesh.vertex_colours.empty()) {
    mesh_.set_constant_attribute(2, glm::vec4(options.base_colour, 1.0f));
  } else {
    mesh_.set_attribute(2, as_floats(mesh.vertex_colours), 3);
  }
  mesh_.set_indices(mesh.indices);
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(camera.view)));
  const glm::vec3 light = glm::normalize(options.light_direction);
  shade_.use();
  gl_.UniformMatrix4fv(shade_.uniform("view"), 1, GL_FALSE, glm::value_ptr(camera.view));
  gl_.UniformMatrix4fv(shade_.uniform("projection"), 1, GL_FALSE,
                       glm::value_ptr(camera.projection));
  gl_.UniformMatrix3fv(shade_.uniform("normal_matrix"), 1, GL_FALSE, glm::value_ptr(normal_matrix));
  gl_.Uniform3fv(shade_.uniform("light_direction"), 1, glm::value_ptr(light));
  gl_.Uniform1f(shade_.uniform("ambient"), options.ambient);
  // A perspective projection has -1 in its last row's z column; an orthographic one 0.
  gl_.Uniform1i(shade_.uniform("perspective"), camera.projection[2][3] != 0.0f ? 1 : 0);
  mesh_.draw();

  // Resolve the samples, read back bottom-up, and flip to top row first.
  gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, framebuffers_[kDraw]);
  gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffers_[kResolve]);
  gl_.BlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
  gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, framebuffers_[kResolve]);
  gl_.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl_.PixelStorei(GL_PACK_ALIGNMENT, 4);
  gl_.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
  gl_.Disable(GL_DEPTH_TEST);
  const std::size_t row = static_cast<std::size_t>(width_) * 4;
  for (int y = 0; y < height_ / 2; ++y) {
    std::swap_ranges(rgba.begin() + y * row, rgba.begin() + (y + 1) * row,
                     rgba.begin() + (height_ - 1 - y) * row);
  }
  throw_on_gl_error(gl_, "preview");
}

}  // namespace sweepd::gpu
