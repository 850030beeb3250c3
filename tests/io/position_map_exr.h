// Reads a sweepd EXR position map back with OpenEXR itself: the positions P.X, P.Y, P.Z
// interleaved per texel (x y z, rows top to bottom, as gpu::PositionMapRenderer fills them) and
// the coverage A, for comparison with the library's own render.
#pragma once

#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <cstddef>
#include <vector>

namespace sweepd::io::test_support {

struct DecodedPositionMap {
  int width = 0, height = 0;
  std::vector<float> positions, coverage;  // width·height·3, width·height
};

inline DecodedPositionMap decode_position_map(Imf::InputFile& file) {
  const Imath::Box2i window = file.header().dataWindow();
  DecodedPositionMap map;
  map.width = window.max.x - window.min.x + 1;
  map.height = window.max.y - window.min.y + 1;
  const std::size_t texels = static_cast<std::size_t>(map.width) * map.height;
  map.positions.resize(texels * 3);
  map.coverage.resize(texels);
  Imf::FrameBuffer frame_buffer;
  const char* channels[3] = {"P.X", "P.Y", "P.Z"};
  for (int c = 0; c < 3; ++c) {
    frame_buffer.insert(channels[c],
                        Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(map.positions.data() + c),
                                   3 * sizeof(float), 3 * sizeof(float) * map.width));
  }
  frame_buffer.insert("A", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(map.coverage.data()),
                                      sizeof(float), sizeof(float) * map.width));
  file.setFrameBuffer(frame_buffer);
  file.readPixels(window.min.y, window.max.y);
  return map;
}

}  // namespace sweepd::io::test_support
