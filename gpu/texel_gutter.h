// TexelGutter: the gutter around a position map's UV islands, so that texture filtering at
// island borders does not pull in zeros. Done on the CPU after readback: on a software
// rasteriser (llvmpipe) n full-target dilation passes cost more than the raster itself, while
// here each pass touches only the texels at the growing border.
//
// Rule (what gpu::PositionMapRenderer documents): `passes` rounds; in each, every texel not yet
// filled that has a filled neighbour takes that neighbour's P and N bit for bit, looking at the
// 4-neighbours (-x, +x, -y, +y) before the diagonals ((-1,-1), (+1,-1), (-1,+1), (+1,+1));
// "filled" means covered (coverage > 0.5) or filled by an earlier round.
// fill() inputs:  width W, height H, coverage W·H (row-major, row y at y·W), passes >= 0.
//        in/out:  positions W·H·3, normals W·H·3 or empty.
// The scratch (a byte per texel and the border lists) is kept between calls: a renderer's one
// TexelGutter allocates only when the map grows.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace sweepd::gpu {

class TexelGutter {
 public:
  void fill(int width, int height, std::span<const float> coverage, int passes,
            std::span<float> positions, std::span<float> normals);

 private:
  std::vector<std::uint8_t> state_;  // per texel: kEmpty, kFilled or kQueued (this round)
  std::vector<std::uint32_t> border_, candidates_, sources_;
};

}  // namespace sweepd::gpu
