#include "gpu/position_map_renderer.h"

#include <chrono>
#include <glm/gtc/type_ptr.hpp>
#include <stdexcept>

namespace sweepd::gpu {
namespace {

constexpr const char* kRasteriseVertex = R"(#version 450 core
layout(location = 0) in vec2 uv;
layout(location = 1) in vec3 position;
layout(location = 2) in vec3 normal;
uniform mat4 view;
uniform mat3 normal_matrix;
out vec3 v_position;
out vec3 v_normal;
void main() {
  gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0);  // u -> x, v -> y over the whole target
  v_position = (view * vec4(position, 1.0)).xyz;
  v_normal = normal_matrix * normal;
}
)";

constexpr const char* kRasteriseFragment = R"(#version 450 core
in vec3 v_position;
in vec3 v_normal;
layout(location = 0) out vec4 out_position;  // w = 1: filled
layout(location = 1) out vec4 out_normal;
layout(location = 2) out float out_coverage;
void main() {
  float length_n = length(v_normal);
  out_position = vec4(v_position, 1.0);
  out_normal = vec4(length_n > 0.0 ? v_normal / length_n : vec3(0.0), 1.0);
  out_coverage = 1.0;
}
)";

enum Texture { kPosition, kNormal, kCoverage };

}  // namespace

PositionMapRenderer::PositionMapRenderer(const Context& context)
    : gl_(context.gl()),
      rasterise_(gl_, "position map", kRasteriseVertex, kRasteriseFragment),
      mesh_(gl_) {
  gl_.GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size_);
}

PositionMapRenderer::~PositionMapRenderer() { delete_targets(); }

void PositionMapRenderer::delete_targets() {
  gl_.DeleteFramebuffers(1, &framebuffer_);
  gl_.DeleteTextures(3, textures_);
  framebuffer_ = 0;
  width_ = height_ = 0;
}

void PositionMapRenderer::resize_targets(int width, int height) {
  if (width == width_ && height == height_) return;
  delete_targets();
  gl_.GenTextures(3, textures_);
  for (int t = 0; t < 3; ++t) {
    gl_.BindTexture(GL_TEXTURE_2D, textures_[t]);
    gl_.TexStorage2D(GL_TEXTURE_2D, 1, t == kCoverage ? GL_R32F : GL_RGBA32F, width, height);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  gl_.GenFramebuffers(1, &framebuffer_);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  const GLenum attachments[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  for (int a = 0; a < 3; ++a)
    gl_.FramebufferTexture2D(GL_FRAMEBUFFER, attachments[a], GL_TEXTURE_2D, textures_[a], 0);
  gl_.DrawBuffers(3, attachments);
  if (gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    delete_targets();
    throw std::runtime_error("position map: float32 render targets of " + std::to_string(width) +
                             "x" + std::to_string(height) + " are not supported by this GL driver");
  }
  width_ = width;
  height_ = height;
}

std::string PositionMapRenderer::validate(const PositionMapMesh& mesh,
                                          const PositionMapOptions& options,
                                          const PositionMapBuffers& buffers) const {
  if (options.width < 1 || options.height < 1 || options.width > max_size_ ||
      options.height > max_size_) {
    return "position map size " + std::to_string(options.width) + "x" +
           std::to_string(options.height) + " is outside 1.." + std::to_string(max_size_);
  }
  if (options.gutter_pixels < 0) return "gutter_pixels is negative";
  const std::size_t vertices = mesh.positions.size();
  for (const std::string& problem :
       {check_vertex_count("UVs", mesh.uvs.size(), vertices),
        mesh.normals.empty() ? std::string()
                             : check_vertex_count("normals", mesh.normals.size(), vertices),
        check_triangle_indices(mesh.indices, vertices)}) {
    if (!problem.empty()) return problem;
  }
  const std::size_t texels = static_cast<std::size_t>(options.width) * options.height;
  if (buffers.positions.size() != texels * 3) return "the positions buffer is not W*H*3 floats";
  if (!buffers.normals.empty() && buffers.normals.size() != texels * 3) {
    return "the normals buffer is neither empty nor W*H*3 floats";
  }
  if (!buffers.normals.empty() && mesh.normals.empty()) {
    return "a normals buffer was given but the mesh has no normals";
  }
  if (!buffers.coverage.empty() && buffers.coverage.size() != texels) {
    return "the coverage buffer is neither empty nor W*H floats";
  }
  return {};
}

void PositionMapRenderer::render(const PositionMapMesh& mesh, const PositionMapOptions& options,
                                 const PositionMapBuffers& buffers, PositionMapTimings* timings) {
  if (const std::string problem = validate(mesh, options, buffers); !problem.empty()) {
    throw std::invalid_argument("position map: " + problem);
  }
  using Clock = std::chrono::steady_clock;
  Clock::time_point stage_start = Clock::now();
  auto end_stage = [&](double PositionMapTimings::*stage) {
    if (!timings) return;
    gl_.Finish();
    const Clock::time_point now = Clock::now();
    timings->*stage = std::chrono::duration<double, std::milli>(now - stage_start).count();
    stage_start = now;
  };
  resize_targets(options.width, options.height);
  gl_.Disable(GL_DEPTH_TEST);
  gl_.Disable(GL_CULL_FACE);
  gl_.Disable(GL_BLEND);
  gl_.Disable(GL_MULTISAMPLE);
  gl_.Viewport(0, 0, width_, height_);

  // 1. Rasterise in UV space into (P, N, A).
  gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int a = 0; a < 3; ++a) gl_.ClearBufferfv(GL_COLOR, a, zero);
  mesh_.set_attribute(0, as_floats(mesh.uvs), 2);
  mesh_.set_attribute(1, as_floats(mesh.positions), 3);
  if (mesh.normals.empty()) {
    mesh_.set_constant_attribute(2, glm::vec4(0.0f));
  } else {
    mesh_.set_attribute(2, as_floats(mesh.normals), 3);
  }
  mesh_.set_indices(mesh.indices);
  end_stage(&PositionMapTimings::upload);
  const glm::mat4 view = options.view.value_or(glm::mat4(1.0f));
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(view)));
  rasterise_.use();
  gl_.UniformMatrix4fv(rasterise_.uniform("view"), 1, GL_FALSE, glm::value_ptr(view));
  gl_.UniformMatrix3fv(rasterise_.uniform("normal_matrix"), 1, GL_FALSE,
                       glm::value_ptr(normal_matrix));
  mesh_.draw();
  end_stage(&PositionMapTimings::raster);

  // 2. Read back: rows come bottom-up, i.e. row 0 = v ≈ 0, as documented. Coverage always:
  // the gutter needs it.
  const std::size_t texels = static_cast<std::size_t>(width_) * height_;
  std::span<float> coverage = buffers.coverage;
  if (coverage.empty()) {
    coverage_scratch_.resize(texels);
    coverage = coverage_scratch_;
  }
  gl_.PixelStorei(GL_PACK_ALIGNMENT, 4);
  gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
  gl_.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl_.ReadPixels(0, 0, width_, height_, GL_RGB, GL_FLOAT, buffers.positions.data());
  if (!buffers.normals.empty()) {
    gl_.ReadBuffer(GL_COLOR_ATTACHMENT1);
    gl_.ReadPixels(0, 0, width_, height_, GL_RGB, GL_FLOAT, buffers.normals.data());
  }
  gl_.ReadBuffer(GL_COLOR_ATTACHMENT2);
  gl_.ReadPixels(0, 0, width_, height_, GL_RED, GL_FLOAT, coverage.data());
  gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
  end_stage(&PositionMapTimings::readback);
  throw_on_gl_error(gl_, "position map");

  // 3. Gutter, on the CPU (gpu/texel_gutter.h says why).
  gutter_.fill(width_, height_, coverage, options.gutter_pixels, buffers.positions,
               buffers.normals);
  end_stage(&PositionMapTimings::gutter);
}

}  // namespace sweepd::gpu
