// PositionMapRenderer: posed positions (and normals) of a UV-mapped mesh rasterised in UV space
// into float32 maps — the "position map" a render farm reads as an EXR.
//
// Inputs (PositionMapMesh): uvs V×2, positions V×3, normals V×3 (or empty), indices 3F.
// Outputs (PositionMapBuffers, caller-owned, row-major, 3 floats per texel for P and N):
//   positions  W·H·3  P = interpolated position (object space, or camera space with a view);
//   normals    W·H·3  N = normalised interpolated normal (optional: leave the span empty);
//   coverage   W·H    A = 1 where a triangle covers the texel centre, else 0 (optional).
// Orientation: texel (x, y) has its centre at uv = ((x + 0.5) / W, (y + 0.5) / H); row y = 0
// holds v ≈ 0. Written as-is to an EXR (whose first row is the top of the image), the map has
// uv (0, 0) at the top-left — glTF's texture convention, so it lines up with the model's
// textures. Sampling is at texel centres (no multisampling): a covered texel holds the
// barycentric interpolation at its centre (float32). Where UV triangles overlap, the later
// triangle wins.
// Gutter: with gutter_pixels = n, n dilation rounds copy, into every uncovered texel next to a
// filled one, that neighbour's P and N (4-neighbours before diagonals), so texture filtering at
// island borders does not pull in zeros. A stays 0 there: A marks real coverage only. The rounds
// run on the CPU after readback (gpu/texel_gutter.h says why).
// Texels neither covered nor reached by the gutter hold P = N = 0.
// Construct and use on the thread where the Context is current; it must not outlive the Context.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpu/egl_context.h"
#include "gpu/mesh_buffers.h"
#include "gpu/shader_program.h"
#include "gpu/texel_gutter.h"

namespace sweepd::gpu {

struct PositionMapMesh {
  std::span<const glm::vec2> uvs;
  std::span<const glm::vec3> positions;
  std::span<const glm::vec3> normals;  // empty: N is not rendered
  std::span<const std::uint32_t> indices;
};

struct PositionMapOptions {
  int width = 1024;
  int height = 1024;
  int gutter_pixels = 0;
  // Set: P = view · (position, 1), N = rotation part of view · normal ("camera" space).
  std::optional<glm::mat4> view;
};

struct PositionMapBuffers {
  std::span<float> positions;  // W·H·3
  std::span<float> normals;    // W·H·3 or empty
  std::span<float> coverage;   // W·H or empty
};

// Where a render's time went, in milliseconds (each GL stage ends with glFinish when asked
// for, so that asynchronous GL work is charged to the stage that queued it).
struct PositionMapTimings {
  double upload = 0, raster = 0, readback = 0, gutter = 0;
};

class PositionMapRenderer {
 public:
  explicit PositionMapRenderer(const Context& context);
  ~PositionMapRenderer();
  PositionMapRenderer(const PositionMapRenderer&) = delete;
  PositionMapRenderer& operator=(const PositionMapRenderer&) = delete;

  // Empty when mesh, options and buffers fit together; otherwise what is wrong, in words.
  std::string validate(const PositionMapMesh& mesh, const PositionMapOptions& options,
                       const PositionMapBuffers& buffers) const;
  // Renders and reads back into buffers; throws std::invalid_argument with validate()'s reason.
  // With `timings`, each stage is finished and timed (benchmarks; it costs the overlap).
  void render(const PositionMapMesh& mesh, const PositionMapOptions& options,
              const PositionMapBuffers& buffers, PositionMapTimings* timings = nullptr);

 private:
  void resize_targets(int width, int height);
  void delete_targets();

  const GlFunctions& gl_;
  GLint max_size_ = 0;
  ShaderProgram rasterise_;
  MeshBuffers mesh_;
  int width_ = 0, height_ = 0;
  GLuint textures_[3] = {};  // P, N, A
  GLuint framebuffer_ = 0;   // rasterises into all three
  std::vector<float> coverage_scratch_;
  TexelGutter gutter_;  // A when the caller does not want it (the gutter does)
};

}  // namespace sweepd::gpu
