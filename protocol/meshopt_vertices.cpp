#include "protocol/meshopt_vertices.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace sweepd::protocol {
namespace {

constexpr std::size_t kPositionVertexBytes = 3 * sizeof(std::int32_t);
constexpr std::size_t kNormalVertexBytes = 4 * sizeof(std::int8_t);
constexpr float kNormalScale = 127.0f;

// round((value − origin) / step) on the grid (halves up), clamped to int32's non-negative range;
// a non-finite value → 0. `inverse_step` is 1 / step: a product, no division per value.
std::int32_t quantise(float value, double origin, double inverse_step) {
  if (!std::isfinite(value)) return 0;
  const double steps = (static_cast<double>(value) - origin) * inverse_step;
  constexpr double kLargest = std::numeric_limits<std::int32_t>::max();
  return steps <= 0.0        ? 0
         : steps >= kLargest ? std::numeric_limits<std::int32_t>::max()
                             : static_cast<std::int32_t>(steps + 0.5);
}

PositionGrid position_grid(std::span<const float> positions) {
  constexpr float kNone = std::numeric_limits<float>::infinity();
  float low[3] = {kNone, kNone, kNone};
  for (std::size_t v = 0; v < positions.size(); v += 3) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const float value = positions[v + axis];
      if (std::isfinite(value)) low[axis] = std::min(low[axis], value);
    }
  }
  for (float& axis : low) axis = axis == kNone ? 0.0f : axis;  // no finite value: 0
  return {Vec3(low[0], low[1], low[2]), kMeshoptPositionStep};
}

std::size_t encode_meshopt_positions(std::span<const float> positions, const PositionGrid& grid,
                                     std::span<std::int32_t> quantised,
                                     std::span<std::uint8_t> encoded) {
  const double origin[3] = {grid.origin.x(), grid.origin.y(), grid.origin.z()};
  const double inverse_step = 1.0 / grid.step;
  for (std::size_t v = 0; v < positions.size(); v += 3) {
    for (std::size_t axis = 0; axis < 3; ++axis)
      quantised[v + axis] = quantise(positions[v + axis], origin[axis], inverse_step);
  }
  return meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), quantised.data(),
                                    positions.size() / 3, kPositionVertexBytes);
}

std::size_t encode_meshopt_normals(std::span<const float> normals, std::span<std::int8_t> quantised,
                                   std::span<std::uint8_t> encoded) {
  const std::size_t vertex_count = normals.size() / 3;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const float value = normals[3 * v + axis];
      const float clamped = std::isnan(value) ? 0.0f : std::clamp(value, -1.0f, 1.0f);
      quantised[4 * v + axis] = static_cast<std::int8_t>(std::lround(clamped * kNormalScale));
    }
    quantised[4 * v + 3] = 0;
  }
  return meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), quantised.data(), vertex_count,
                                    kNormalVertexBytes);
}

}  // namespace

std::size_t meshopt_bytes_bound(std::size_t vertex_count, bool normals) {
  return meshopt_encodeVertexBufferBound(vertex_count, kPositionVertexBytes) +
         (normals ? meshopt_encodeVertexBufferBound(vertex_count, kNormalVertexBytes) : 0);
}

PositionGrid MeshoptEncoder::encode(std::span<const float> positions,
                                    std::span<const float> normals) {
  const std::size_t vertex_count = positions.size() / 3;
  const PositionGrid grid = position_grid(positions);
  quantised_positions_.resize(positions.size());
  positions_.resize(meshopt_encodeVertexBufferBound(vertex_count, kPositionVertexBytes));
  positions_size_ = encode_meshopt_positions(positions, grid, quantised_positions_, positions_);
  normals_size_ = 0;
  if (!normals.empty()) {
    quantised_normals_.resize(4 * (normals.size() / 3));
    normals_.resize(meshopt_encodeVertexBufferBound(normals.size() / 3, kNormalVertexBytes));
    normals_size_ = encode_meshopt_normals(normals, quantised_normals_, normals_);
  }
  return grid;
}

bool decode_meshopt_positions(std::span<const std::uint8_t> encoded, const PositionGrid& grid,
                              std::span<float> positions) {
  static_assert(sizeof(float) == sizeof(std::int32_t));
  if (positions.size() % 3 != 0) return false;
  // The codec writes the int32 grid coordinates over the floats' own storage, then each is
  // read back (memcpy: no aliasing) and replaced by its position.
  if (meshopt_decodeVertexBuffer(positions.data(), positions.size() / 3, kPositionVertexBytes,
                                 encoded.data(), encoded.size()) != 0)
    return false;
  const float origin[3] = {grid.origin.x(), grid.origin.y(), grid.origin.z()};
  for (std::size_t v = 0; v < positions.size(); v += 3) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      std::int32_t q = 0;
      std::memcpy(&q, &positions[v + axis], sizeof q);
      positions[v + axis] = origin[axis] + grid.step * static_cast<float>(q);
    }
  }
  return true;
}

bool decode_meshopt_normals(std::span<const std::uint8_t> encoded, std::span<float> normals) {
  if (normals.size() % 3 != 0) return false;
  const std::size_t vertex_count = normals.size() / 3;
  // The codec's 4 bytes per vertex fill the first third of the floats' storage; they are
  // widened from the last vertex back, so each vertex's bytes are read before floats cover them.
  auto* bytes = reinterpret_cast<unsigned char*>(normals.data());
  if (meshopt_decodeVertexBuffer(bytes, vertex_count, kNormalVertexBytes, encoded.data(),
                                 encoded.size()) != 0)
    return false;
  for (std::size_t v = vertex_count; v-- > 0;) {
    std::int8_t q[3];
    std::memcpy(q, bytes + kNormalVertexBytes * v, sizeof q);
    for (std::size_t axis = 0; axis < 3; ++axis)
      normals[3 * v + axis] = std::max(static_cast<float>(q[axis]) / kNormalScale, -1.0f);
  }
  return true;
}

}  // namespace sweepd::protocol
