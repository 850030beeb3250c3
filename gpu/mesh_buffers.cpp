#include "gpu/mesh_buffers.h"

namespace sweepd::gpu {

std::string check_vertex_count(const char* what, std::size_t count, std::size_t vertices) {
  if (count == vertices) return {};
  return "the mesh has " + std::to_string(count) + " " + what + " for " + std::to_string(vertices) +
         " vertices (one per vertex needed)";
}

std::string check_triangle_indices(std::span<const std::uint32_t> indices, std::size_t vertices) {
  if (indices.size() % 3 != 0) return "the index count is not a multiple of 3";
  for (std::uint32_t index : indices) {
    if (index >= vertices) {
      return "index " + std::to_string(index) + " is out of range (" + std::to_string(vertices) +
             " vertices)";
    }
  }
  return {};
}
MeshBuffers::MeshBuffers(const GlFunctions& gl) : gl_(gl) {
  gl_.GenVertexArrays(1, &vertex_array_);
  gl_.GenBuffers(1, &index_buffer_);
  gl_.GenBuffers(kMaxAttributes, attribute_buffers_);
}

MeshBuffers::~MeshBuffers() {
  gl_.DeleteBuffers(kMaxAttributes, attribute_buffers_);
  gl_.DeleteBuffers(1, &index_buffer_);
  gl_.DeleteVertexArrays(1, &vertex_array_);
}

void MeshBuffers::set_attribute(int location, std::span<const float> values, int components) {
  gl_.BindVertexArray(vertex_array_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, attribute_buffers_[location]);
  // Re-specifying the store lets the driver orphan the old one instead of waiting on a draw.
  gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(values.size_bytes()), values.data(),
                 GL_STREAM_DRAW);
  gl_.VertexAttribPointer(location, components, GL_FLOAT, GL_FALSE, 0, nullptr);
  gl_.EnableVertexAttribArray(location);
}

void MeshBuffers::set_constant_attribute(int location, const glm::vec4& value) {
  gl_.BindVertexArray(vertex_array_);
  gl_.DisableVertexAttribArray(location);
  gl_.VertexAttrib4f(location, value.x, value.y, value.z, value.w);
}

void MeshBuffers::set_indices(std::span<const std::uint32_t> indices) {
  gl_.BindVertexArray(vertex_array_);
  gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);
  gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size_bytes()),
                 indices.data(), GL_STREAM_DRAW);
  index_count_ = static_cast<GLsizei>(indices.size());
}

void MeshBuffers::draw() const {
  gl_.BindVertexArray(vertex_array_);
  gl_.DrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
}

}  // namespace sweepd::gpu
