// MeshBuffers: a vertex array object with float attribute buffers and a triangle index buffer,
// re-uploaded whole each frame (the driver orphans the previous storage).
//
// Inputs: per-vertex float arrays (count × components, tightly packed, e.g. glm::vec3 spans via
// as_floats) at attribute locations 0 .. kMaxAttributes-1; uint32 triangle indices (3 per
// triangle). draw() binds the VAO (a core profile draws nothing without one) and draws them.
// Use on the context's thread.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <string>

#include "gpu/gl_functions.h"

namespace sweepd::gpu {

template <class Vector>
std::span<const float> as_floats(std::span<const Vector> vectors) {
  static_assert(sizeof(Vector) == sizeof(float) * Vector::length(), "vector must be packed");
  return {reinterpret_cast<const float*>(vectors.data()), vectors.size() * Vector::length()};
}

// Input checks shared by the renderers (empty string = fine, else the reason in words):
// a per-vertex array with `count` entries of `what` ("normals") for `vertices` vertices,
std::string check_vertex_count(const char* what, std::size_t count, std::size_t vertices);
// and triangle indices: a multiple of 3, each below `vertices`.
std::string check_triangle_indices(std::span<const std::uint32_t> indices, std::size_t vertices);

class MeshBuffers {
 public:
  static constexpr int kMaxAttributes = 4;

  explicit MeshBuffers(const GlFunctions& gl);
  ~MeshBuffers();
  MeshBuffers(const MeshBuffers&) = delete;
  MeshBuffers& operator=(const MeshBuffers&) = delete;

  void set_attribute(int location, std::span<const float> values, int components);
  // The attribute reads `value` for every vertex (no buffer).
  void set_constant_attribute(int location, const glm::vec4& value);
  void set_indices(std::span<const std::uint32_t> indices);
  void draw() const;

 private:
  const GlFunctions& gl_;
  GLuint vertex_array_ = 0;
  GLuint index_buffer_ = 0;
  GLuint attribute_buffers_[kMaxAttributes] = {};
  GLsizei index_count_ = 0;
};

}  // namespace sweepd::gpu
