// MeshoptVertices: PosedVertices' compact Meshopt format (protocol 1.5) — positions on a fixed
// grid and normals as signed 8-bit, each stream through meshoptimizer's vertex codec (version 0,
// as Debian 12's libmeshoptimizer 0.18 writes it; npm `meshoptimizer` decodes it too). Every
// reply decodes alone: the grid travels with it, nothing refers to an earlier reply.
//
// Positions: q = round((p − origin) / step), int32 x, y, z per vertex (12-byte vertices), with
//   origin the per-axis minimum of the reply's positions and step kMeshoptPositionStep (0.18 mm),
//   so |decoded − p| ≤ step / 2 = 0.09 mm plus float32 rounding (under 1 µm within 100 m): within
//   issue 18's 0.1 mm. A finer grid costs bytes: 0.1 mm gives 2.64× fewer than float32 on the 72k
//   mannequin, 0.18 mm 2.72× (and 2.97× / 3.17× on the 14.5k male).
//   Decoded: p = origin + step * q. A non-finite coordinate is encoded as q = 0 (the origin).
// Normals: q = round(clamp(n, −1, 1) * 127), int8 x, y, z and a 0 per vertex (4-byte vertices);
//   decoded n = max(q / 127, −1), |decoded − n| ≤ 1/254 per component (not renormalised).
//
// meshopt_bytes_bound(n, normals) the codec's bound for n vertices (its worst case).
// MeshoptEncoder::encode(positions, normals)
//                       positions (3n floats), normals (3n, or empty for none) → the encoded
//                       streams, positions() and normals() (empty for no normals), valid until
//                       the next encode; returns the positions' grid. Its scratch and output
//                       are kept between calls (grown to the largest n seen): no allocation per
//                       reply once warm.
// decode_meshopt_positions(encoded, grid, positions) / decode_meshopt_normals(encoded, normals)
//                       → 3n floats, using `positions` / `normals` as the codec's output buffer
//                       (no scratch, no allocation), n = out.size() / 3. False when the bytes
//                       are not a whole codec stream of n vertices (truncated, corrupt, trailing
//                       bytes); `out` then holds garbage. The codec does not record n, so the
//                       caller takes it from the reply (PosedVertices.vertex_count).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "protocol/sweepd_generated.h"

namespace sweepd::protocol {

inline constexpr float kMeshoptPositionStep = 1.8e-4f;  // metres: error ≤ 0.09 mm

struct PositionGrid {
  Vec3 origin{};
  float step = kMeshoptPositionStep;
};

// The most bytes encode() can write for n vertices: positions, and normals when asked for.
std::size_t meshopt_bytes_bound(std::size_t vertex_count, bool normals);

class MeshoptEncoder {
 public:
  PositionGrid encode(std::span<const float> positions, std::span<const float> normals);
  std::span<const std::uint8_t> positions() const { return {positions_.data(), positions_size_}; }
  std::span<const std::uint8_t> normals() const { return {normals_.data(), normals_size_}; }

 private:
  std::vector<std::int32_t> quantised_positions_;
  std::vector<std::int8_t> quantised_normals_;
  std::vector<std::uint8_t> positions_, normals_;
  std::size_t positions_size_ = 0, normals_size_ = 0;
};

bool decode_meshopt_positions(std::span<const std::uint8_t> encoded, const PositionGrid& grid,
                              std::span<float> positions);
bool decode_meshopt_normals(std::span<const std::uint8_t> encoded, std::span<float> normals);

}  // namespace sweepd::protocol
